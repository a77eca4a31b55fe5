"""The final project's contest, judged as a TA judges it: where the arm rests (the lab's own
offsets, :mod:`crslab.contest.offsets`), running a lab until its motion ends
(:mod:`crslab.contest.run`, :mod:`crslab.contest.motion`), the four tasks judged from the run's
log (:mod:`crslab.contest.tasks`), the scorecard (:mod:`crslab.contest.scorecard`), its picture
(:mod:`crslab.contest.card_plot`) and the sink that sends it to ``crslab serve``'s page
(:mod:`crslab.contest.page_card`)."""
