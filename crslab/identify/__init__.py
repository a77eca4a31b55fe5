"""Calibrating the simulated arm to a real one (``crslab identify``, ``crslab friction``):
recordings of the real arm (:mod:`.recording`), where they lie on a simulated run (:mod:`.align`),
running the lab that made them (:mod:`.runs`); the course's friction table (:mod:`.friction_table`)
and crslab's Lab 3 lab that measures one (:mod:`.friction_lab`, :mod:`.friction_report`); the
least-squares fit of the plant to all of them (:mod:`.fit`) and its cross-validation
(:mod:`.cross_validation`); step-response numbers (:mod:`.metrics`) and what is printed and drawn
(:mod:`.report`)."""
