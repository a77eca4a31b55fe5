"""The final project's contest: the scorecard of a run (:mod:`crslab.contest.scorecard`), its
picture (:mod:`crslab.contest.card_plot`) and running a lab for it (:mod:`crslab.contest.run`)."""
