"""Windows into a running lab: the serial pseudo-terminal, live variables and MuJoCo's viewer."""
