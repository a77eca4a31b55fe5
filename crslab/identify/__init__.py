"""Calibrating the simulated arm to a real one (``crslab identify``): recordings of the real arm
(:mod:`.recording`), where they lie on a simulated run (:mod:`.align`), running the lab that made
them (:mod:`.runs`), the least-squares fit of the plant (:mod:`.fit`), step-response numbers
(:mod:`.metrics`) and what is printed and drawn (:mod:`.report`)."""
