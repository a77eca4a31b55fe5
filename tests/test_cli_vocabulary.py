"""One vocabulary across commands: a mistyped option or command is said by the command it was
given to, with the nearest right one and that command's help; every command that writes a file
or folder takes -o; ``crslab --help`` groups the commands by who uses them; ``crslab help CMD``."""

import argparse
import subprocess
import sys

import pytest

from crslab.cli import GROUPS, build_parser


def crslab(*args):
    return subprocess.run([sys.executable, "-m", "crslab", *map(str, args)], capture_output=True, text=True,
                          timeout=120)


@pytest.mark.parametrize("argv, said", [
    (["sim", "--fsat"], "crslab sim: error: unrecognized argument: --fsat (did you mean --fast?) "
                        "(see 'crslab sim --help')"),
    (["grade", "subs", "--referense", "r.c"], "crslab grade: error: unrecognized argument: --referense "
                                              "(did you mean --reference?)"),
    (["serial", "read", "Kp1", "--dri", "ports"], "crslab serial read: error: unrecognized arguments: --dri "
                                                  "ports (did you mean --dir?)"),
    (["sweep", "--samples=4", "--vary-it=x"], "crslab sweep: error: unrecognized argument: --vary-it=x "
                                              "(did you mean --vary?)"),
    (["smi", "--fast"], "crslab: error: no command 'smi' (did you mean sim?) (see 'crslab --help')"),
    (["help", "grdae"], "crslab help: no command 'grdae' (did you mean grade?); 'crslab help' lists them"),
])
def test_a_mistyped_word_is_said_by_its_command_with_the_nearest_right_one(argv, said):
    r = crslab(*argv)
    assert r.returncode == 2 and r.stdout == ""
    assert r.stderr.count("\n") == 1 and said in r.stderr, r.stderr


def test_an_option_far_from_every_other_gets_no_guess():
    r = crslab("sim", "--qqqqqqqq")
    assert r.returncode == 2
    assert r.stderr == "crslab sim: error: unrecognized argument: --qqqqqqqq (see 'crslab sim --help')\n"


def subcommands(parser=None, prefix=""):
    """Every (sub)command's name and parser, ``serial read`` included."""
    parser = parser or build_parser()
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for name, sub in action.choices.items():
                yield f"{prefix}{name}", sub
                yield from subcommands(sub, f"{prefix}{name} ")


WRITERS = {"sim": "--transcript", "debug": "--transcript", "record": "--output", "check": "--junit",
           "grade": "--out", "sweep": "--output", "identify": "--output", "traj": "--output",
           "workspace": "--output", "plot": "--output", "map": "--output", "new": "--output",
           "friction": "--output", "serial scope": "--rrd", "contest": "--output"}


def test_every_command_that_writes_a_file_or_folder_takes_o():
    parsers = dict(subcommands())
    for name, long_option in WRITERS.items():
        options = {o: a for a in parsers[name]._actions for o in a.option_strings}
        assert "-o" in options and options["-o"] is options[long_option], name
    # and no other command has an option that writes a file without -o
    writes = {"--transcript", "--output", "--out", "--junit"}
    for name, parser in parsers.items():
        options = {o for a in parser._actions for o in a.option_strings}
        assert not (options & writes) or name in WRITERS, name


def test_debug_takes_fast_as_sim_does():
    parser = build_parser()
    assert parser.parse_args(["debug", "--fast"]).fast is True
    assert parser.parse_args(["sim", "--fast"]).fast is True
    r = crslab("debug", "--fast", "--speed", "2")
    assert r.returncode == 2 and "not allowed with argument" in r.stderr


def test_help_groups_every_command_by_who_uses_it_students_first():
    parser = build_parser()
    grouped = [name for names in GROUPS.values() for name in names]
    assert sorted(grouped) == sorted(parser.commands) and len(set(grouped)) == len(grouped)
    assert GROUPS["for students"][:5] == ["sim", "debug", "record", "check", "new"]
    assert {"grade", "sweep", "identify"} <= set(GROUPS["for TAs and instructors"])
    assert {"fk", "ik", "traj"} <= set(GROUPS["the kinematics toolbox"])
    r = crslab("--help")
    assert r.returncode == 0
    text = r.stdout
    titles = [text.index(f"\n{title}:\n") for title in GROUPS]
    assert titles == sorted(titles)  # in GROUPS' order, students first
    for title, names in GROUPS.items():
        block = text[text.index(f"\n{title}:\n") + 1:].split("\n\n")[0].splitlines()[1:]
        assert [line.split()[0] for line in block] == names, title


def test_help_command_shows_the_command_s_own_help():
    r = crslab("help", "sim")
    assert r.returncode == 0 and r.stdout == crslab("sim", "--help").stdout
    assert r.stdout.startswith("usage: crslab sim ")
    assert crslab("help").stdout == crslab("--help").stdout


def test_new_takes_options_between_its_words(tmp_path):
    args = build_parser().parse_args(["new", "lab2", "--gen", "A", "mine.c"])
    assert (args.lab, args.gen, str(args.file)) == ("lab2", "A", "mine.c")
