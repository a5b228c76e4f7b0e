"""`acausal show`, `acausal list` and `acausal check` reach their commands through main()."""

from pathlib import Path

from acausal.tools.cli import main

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def test_show_prints_the_declarations(capsys):
    assert main(["show", "library.blocks.Step"]) == 0
    out = capsys.readouterr().out
    assert "height" in out and "startTime" in out and "s" in out.split()


def test_show_an_unknown_class_suggests_the_close_name(capsys):
    assert main(["show", "library.blocks.Stp"]) == 2
    assert "library.blocks.Step" in capsys.readouterr().err


def test_list_names_the_components_of_a_package(capsys):
    assert main(["list", "library.blocks"]) == 0
    out = capsys.readouterr().out
    assert "Step" in out and "Sine" in out


def test_check_a_consistent_example(capsys):
    assert main(["check", str(EXAMPLES / "first.py")]) == 0
    assert "First" in capsys.readouterr().out


def test_the_commands_appear_in_the_help(capsys):
    assert main(["--help"]) == 0
    out = capsys.readouterr().out
    for command in ("show", "list", "check"):
        assert command in out
