"""Every command-line entry point answers ``--help`` with its usage and exit code 0."""
import argparse
import subprocess
import sys

import pytest

from exudyn_wheelrail.cli import build_parser, main


def _subcommands():
    parser = build_parser()
    actions = [a for a in parser._actions if isinstance(a, argparse._SubParsersAction)]
    assert len(actions) == 1
    return sorted(actions[0].choices)


SUBCOMMANDS = _subcommands()


def test_the_subcommand_list_is_the_documented_one():
    # the docstring of the cli package is the user's list of commands: every parser is in it and vice versa
    import exudyn_wheelrail.cli as cli
    documented = {line.split()[0] for line in cli.__doc__.split("Commands\n--------\n")[1].split("\n\n")[0].splitlines()
                  if line.strip()}
    assert documented == set(SUBCOMMANDS)


@pytest.mark.parametrize("command", SUBCOMMANDS)
def test_help_of_every_subcommand(command, capsys):
    with pytest.raises(SystemExit) as exit_info:
        main([command, "--help"])
    assert exit_info.value.code == 0
    out = capsys.readouterr().out
    assert out.startswith("usage:") and command in out.splitlines()[0]
    # every option of the subcommand is listed in its help
    sub = next(a for a in build_parser()._actions if isinstance(a, argparse._SubParsersAction)).choices[command]
    for action in sub._actions:
        for flag in action.option_strings:
            assert flag in out, (command, flag)


def test_help_through_the_module_entry_point():
    for args in ([], ["rtri"], ["rtri-sweep"]):
        r = subprocess.run([sys.executable, "-m", "exudyn_wheelrail", *args, "--help"], capture_output=True,
                           text=True, timeout=120)
        assert r.returncode == 0 and r.stdout.startswith("usage:") and not r.stderr, (args, r.stderr)
