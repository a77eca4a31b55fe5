"""The final project's contest: the scorecard of a run (:mod:`crslab.contest.scorecard`) and its
picture (:mod:`crslab.contest.card_plot`); ``crslab contest`` runs a lab for it
(:mod:`crslab.cli.contest_commands`)."""
