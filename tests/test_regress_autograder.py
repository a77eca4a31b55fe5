"""`crslab grade --report` writes Gradescope's and PrairieLearn's results files as each platform
documents them: the schemas below are written from the platforms' own specifications (Gradescope's
"Autograder Specifications", PrairieLearn's "External Grading: Grading results"), and every file
crslab writes is validated against them."""

import json
import shutil
from pathlib import Path

import jsonschema
import pytest

from crslab.cli import main

LABS = Path(__file__).parent / "labs"
REFERENCE = Path(__file__).resolve().parents[1] / "csrc" / "labs" / "lab1_kinematics.c"
VISIBILITY = {"enum": ["hidden", "after_due_date", "after_published", "visible"]}
FORMAT = {"enum": ["text", "html", "simple_format", "md", "ansi"]}

GRADESCOPE = {  # gradescope-autograders.readthedocs.io/en/latest/specs/ "Output format"
    "type": "object",
    "properties": {
        "score": {"type": "number"},
        "execution_time": {"type": "number"},
        "output": {"type": "string"},
        "output_format": FORMAT,
        "test_output_format": FORMAT,
        "test_name_format": FORMAT,
        "visibility": VISIBILITY,
        "stdout_visibility": VISIBILITY,
        "extra_data": {"type": "object"},
        "tests": {
            "type": "array",
            "items": {
                "type": "object",
                "properties": {
                    "score": {"type": "number"},
                    "max_score": {"type": "number"},
                    "status": {"enum": ["passed", "failed"]},
                    "name": {"type": "string"},
                    "name_format": FORMAT,
                    "number": {"type": "string"},
                    "output": {"type": "string"},
                    "output_format": FORMAT,
                    "tags": {"type": "array", "items": {"type": "string"}},
                    "visibility": VISIBILITY,
                    "extra_data": {"type": "object"},
                },
                "additionalProperties": False,
            },
        },
        "leaderboard": {"type": "array", "items": {"type": "object", "required": ["name", "value"]}},
    },
    "additionalProperties": False,
    # "score: optional, but required if not on each test case"
    "anyOf": [
        {"required": ["score"]},
        {"required": ["tests"], "properties": {"tests": {"items": {"required": ["score"]}}}},
    ],
}

IMAGES = {
    "type": "array",
    "items": {
        "anyOf": [
            {"type": "string"},
            {
                "type": "object",
                "required": ["url"],
                "properties": {"url": {"type": "string"}, "label": {"type": "string"}},
            },
        ]
    },
}
PRAIRIELEARN = {  # prairielearn.readthedocs.io/en/latest/externalGrading/ "Grading results"
    "type": "object",
    "properties": {
        "gradable": {"type": "boolean"},
        "score": {"type": "number", "minimum": 0.0, "maximum": 1.0},
        "format_errors": {"anyOf": [{"type": "string"}, {"type": "array", "items": {"type": "string"}}]},
        "message": {"type": "string"},
        "output": {"type": "string"},
        "images": IMAGES,
        "tests": {
            "type": "array",
            "items": {
                "type": "object",
                "required": ["name"],
                "properties": {
                    "name": {"type": "string"},
                    "description": {"type": "string"},
                    "points": {"type": "number"},
                    "max_points": {"type": "number"},
                    "message": {"type": "string"},
                    "output": {"type": "string"},
                    "images": IMAGES,
                },
            },
        },
    },
    # "If the submission is gradable, the result only has one mandatory field: score"
    "if": {"not": {"properties": {"gradable": {"const": False}}, "required": ["gradable"]}},
    "then": {"required": ["score"]},
}
PL_MAX_BYTES = 1024 * 1024  # "this file should be limited to 1 MB"


def check(platform, path):
    data = json.loads(path.read_text())
    jsonschema.validate(data, GRADESCOPE if platform == "gradescope" else PRAIRIELEARN)
    if platform == "prairielearn":
        assert path.stat().st_size < PL_MAX_BYTES
    return data


def test_the_schemas_catch_what_the_platforms_reject():
    with pytest.raises(jsonschema.ValidationError):
        jsonschema.validate({"tests": [{"name": "no score anywhere"}]}, GRADESCOPE)
    with pytest.raises(jsonschema.ValidationError):
        jsonschema.validate({"score": 1, "tests": [{"score": 1, "status": "ok"}]}, GRADESCOPE)
    with pytest.raises(jsonschema.ValidationError):
        jsonschema.validate({"gradable": True, "score": 3}, PRAIRIELEARN)
    with pytest.raises(jsonschema.ValidationError):
        jsonschema.validate({"message": "no score"}, PRAIRIELEARN)
    jsonschema.validate({"gradable": False, "format_errors": "x"}, PRAIRIELEARN)


@pytest.fixture(scope="module")
def tests_file(tmp_path_factory):
    folder = tmp_path_factory.mktemp("autograder")
    (folder / "short_tour.toml").write_text(
        (Path(__file__).resolve().parents[1] / "crslab" / "scenario" / "builtin" / "tour.toml").read_text()
    )
    path = folder / "tests.toml"
    path.write_text(
        '[[test]]\nname = "Lab 1 on the tour"\nscenario = "tour"\nduration = 6.0\npoints = 6\n\n'
        '[[test]]\nscenario = "short_tour.toml"\nduration = 4.0\npoints = 4\n'
    )
    return path


@pytest.mark.parametrize("platform", ["gradescope", "prairielearn"])
def test_a_passing_and_a_failing_submission(tmp_path, tests_file, platform, capsys):
    good, wrong = tmp_path / "good", tmp_path / "wrong"
    good.mkdir()
    wrong.mkdir()
    shutil.copy(LABS / "lab1_own_ik.c", good / "lab1.c")
    (good / "README.txt").write_text("not a lab")
    text = (LABS / "lab1_own_ik.c").read_text()
    (wrong / "lab1.c").write_text(text.replace("atan2(-s_in, r_in)", "atan2(s_in, r_in)"))
    assert (
        main(
            [
                "grade",
                str(good),
                "--reference",
                str(REFERENCE),
                "--tests",
                str(tests_file),
                "--report",
                platform,
                str(tmp_path / "good.json"),
            ]
        )
        == 0
    )
    assert (
        main(
            [
                "grade",
                str(wrong),
                "--reference",
                str(REFERENCE),
                "--tests",
                str(tests_file),
                "--report",
                platform,
                str(tmp_path / "res" / "wrong.json"),
            ]
        )
        == 1
    )
    ok, bad = check(platform, tmp_path / "good.json"), check(platform, tmp_path / "res" / "wrong.json")
    assert [t["name"] for t in ok["tests"]] == ["Lab 1 on the tour", "short_tour"]
    if platform == "gradescope":
        assert ok["score"] == 10 and [t["status"] for t in ok["tests"]] == ["passed", "passed"]
        assert bad["score"] == 4 and [(t["score"], t["max_score"], t["status"]) for t in bad["tests"]] == [
            (0, 6, "failed"),
            (4, 4, "passed"),
        ]
        failing = bad["tests"][0]["output"]
    else:
        assert ok["gradable"] and ok["score"] == 1.0
        assert bad["score"] == 0.4 and [(t["points"], t["max_points"]) for t in bad["tests"]] == [
            (0, 6),
            (4, 4),
        ]
        failing = bad["tests"][0]["output"]
    # wrong.c's elbow sign shows from 4.1 s (the 4 s test ends before its first print)
    assert failing.startswith("mismatch: ") and "expected: 0.00 -24.06 13.75" in failing
    assert "lines it printed:" in failing
    out = capsys.readouterr().out
    assert "Lab 1 on the tour: mismatch (0 of 6 points)" in out and "lab1.c: 4 of 10 points" in out


@pytest.mark.parametrize("platform", ["gradescope", "prairielearn"])
def test_a_submission_that_does_not_compile_or_is_missing(tmp_path, platform):
    broken = tmp_path / "broken"
    broken.mkdir()
    shutil.copy(LABS / "does_not_compile.c", broken / "lab.c")
    out = tmp_path / "r.json"
    assert (
        main(
            [
                "grade",
                str(broken),
                "--reference",
                str(REFERENCE),
                "--duration",
                "5",
                "--points",
                "3",
                "--report",
                platform,
                str(out),
            ]
        )
        == 1
    )
    data = check(platform, out)
    if platform == "gradescope":
        assert data["score"] == 0 and data["tests"][0]["status"] == "failed"
        assert "lab.c:9:13: error:" in data["tests"][0]["output"]
    else:  # not gradable: the student keeps the attempt, and reads why
        assert data["gradable"] is False and "lab.c:9:13: error:" in data["format_errors"][0]
    empty = tmp_path / "empty"
    empty.mkdir()
    assert main(["grade", str(empty), "--reference", str(REFERENCE), "--report", platform, str(out)]) == 1
    data = check(platform, out)
    assert "expected exactly one lab file (.c or .cpp) in the submission, found 0" in json.dumps(data)


def test_a_bad_tests_file_is_one_line(tmp_path, capsys):
    bad = tmp_path / "tests.toml"
    bad.write_text('[[test]]\nscenario = "tour"\npoints = -1\n')
    sub = tmp_path / "sub"
    sub.mkdir()
    shutil.copy(LABS / "lab1_own_ik.c", sub / "lab1.c")
    assert (
        main(
            [
                "grade",
                str(sub),
                "--reference",
                str(REFERENCE),
                "--tests",
                str(bad),
                "--report",
                "gradescope",
                str(tmp_path / "r.json"),
            ]
        )
        == 2
    )
    assert capsys.readouterr().err.strip() == f"crslab grade: {bad}:3: points: must be at least 0, got -1"
    assert not (tmp_path / "r.json").exists()
