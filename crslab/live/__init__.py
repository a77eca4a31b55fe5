"""Live variables: read and write a running lab's watched variables from typed commands. (The
serial pseudo-terminal and MuJoCo's viewer are sinks: :mod:`crslab.sinks`.)"""
