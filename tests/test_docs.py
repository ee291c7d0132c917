"""The README and the documentation pages (docs/README.md, docs/tutorial.md, docs/validation.md, docs/performance.md,
docs/cli.md) say what the product does today:

* the README's first two commands are the install and the test command that CI runs (``.ci/fresh-venv``);
* every relative link and every repository path named in the README exists;
* the README's Python blocks run as written (each in a new namespace, in an empty working directory);
* every ``python -m exudyn_wheelrail ...`` command of these pages is accepted by the command-line parser, and every
  ``python <script>`` names an existing file;
* docs/cli.md holds the ``--help`` text of every command as the parser prints it (at 100 columns).  After a change
  of the command line, regenerate those blocks with ``python tests/test_docs.py --write-cli``;
* the pages describe the product, not the work on it (no milestones, issues or unfinished work); so do the
  package's, the benchmarks', the examples' and the tests' comments, docstrings and messages, and the other READMEs.
"""
from __future__ import annotations

import argparse
import os
import re
import shlex
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
README = ROOT / "README.md"
DOCS = ROOT / "docs"
CLI_DOC = DOCS / "cli.md"
PAGES = (README, DOCS / "README.md", DOCS / "tutorial.md", DOCS / "validation.md", DOCS / "performance.md", CLI_DOC)
#: words of the work on the product, not of the product: a milestone, an issue number, a provisional state
WORK_WORDS = r"milestone|\bissues?[ -]?#?\d|\bfor now\b|\bTODO\b|being (?:completed|validated)"
#: more of them, for prose (in code "not yet assembled" is a state of an Exudyn system)
PAGE_WORK_WORDS = WORK_WORDS + r"|\bnot yet\b|\bwill be\b|\bfollow \("
#: text files beside the pages that are held to WORK_WORDS
SOURCE_GLOBS = ("exudyn_wheelrail/**/*.py", "benchmarks/**/*.py", "benchmarks/README.md", "examples/**/*.py",
                "examples/**/*.md", "examples/**/*.toml", "tests/**/*.py", "vehicles/*.md")
HELP_COLUMNS = 100
TOP = "python -m exudyn_wheelrail"          # marker name of the top-level help in docs/cli.md
HELP_BLOCK = re.compile(r"<!-- help: (.+?) -->\n```text\n(.*?)```\n<!-- /help -->", re.S)


def _blocks(text: str, *langs: str) -> list[str]:
    return [m.group(2) for m in re.finditer(r"```(\w*)\n(.*?)```", text, re.S) if m.group(1) in langs]


def _commands(text: str) -> list[str]:
    """Shell commands of the bash/sh blocks: continuation lines joined, trailing comments dropped."""
    out = []
    for block in _blocks(text, "bash", "sh"):
        for line in block.replace("\\\n", " ").splitlines():
            line = re.split(r"\s+#\s", line, maxsplit=1)[0].strip()
            out.extend(part.strip() for part in line.split("&&") if part.strip())
    return out


def cli_help_texts() -> dict[str, str]:
    """``{name: help text}`` of ``python -m exudyn_wheelrail [<command>] --help`` at HELP_COLUMNS columns (the
    top level under the name TOP)."""
    from exudyn_wheelrail.cli import build_parser
    old = os.environ.get("COLUMNS")
    os.environ["COLUMNS"] = str(HELP_COLUMNS)
    try:
        parser = build_parser()
        sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
        texts = {TOP: parser.format_help()}
        texts.update({name: p.format_help() for name, p in sub.choices.items()})
    finally:
        if old is None:
            del os.environ["COLUMNS"]
        else:
            os.environ["COLUMNS"] = old
    return texts


def write_cli_doc(path: Path = CLI_DOC) -> list[str]:
    """Replace every ``<!-- help: NAME -->`` block of ``path`` with the parser's current help; returns the names
    of the commands that have no block yet (add a section with an empty block for them, then run this again)."""
    texts = cli_help_texts()
    text = path.read_text(encoding="utf-8")
    new = HELP_BLOCK.sub(lambda m: f"<!-- help: {m.group(1)} -->\n```text\n{texts[m.group(1)].rstrip()}\n```\n"
                                   "<!-- /help -->", text)
    path.write_text(new, encoding="utf-8")
    return sorted(set(texts) - {m.group(1) for m in HELP_BLOCK.finditer(new)})


# ---------------------------------------------------------------------------------------------------------------
def test_the_readme_starts_with_the_commands_ci_runs():
    first = _blocks(README.read_text(encoding="utf-8"), "bash")[0]
    lines = [re.split(r"\s+#\s", line, maxsplit=1)[0].strip() for line in first.strip().splitlines()]
    assert lines == ['python -m pip install -c constraints.txt -e ".[test]" && python examples/contact_geometry.py',
                     "python -m pytest -q"]
    ci = (ROOT / ".ci" / "fresh-venv").read_text(encoding="utf-8")
    assert 'pinned) python -m pip install --quiet -c constraints.txt -e ".[test]"' in ci
    assert "cmd=(python -m pytest -q)" in ci
    assert "bash .ci/fresh-venv pinned" in (ROOT / ".ci" / "run").read_text(encoding="utf-8")


@pytest.mark.parametrize("page", PAGES, ids=lambda p: str(p.relative_to(ROOT)))
def test_relative_links_resolve(page):
    text = page.read_text(encoding="utf-8")
    for link in re.findall(r"\]\(([^)\s]+)\)", text):
        if re.match(r"[a-z]+:", link) or link.startswith("#"):
            continue
        assert (page.parent / link.split("#")[0]).exists(), (page.name, link)


def test_repository_paths_named_in_the_readme_exist():
    text = README.read_text(encoding="utf-8")
    paths = re.findall(r"`((?:exudyn_wheelrail|tests|examples|benchmarks|vehicles|docs|\.ci)/[^`\s]*)`", text)
    assert len(paths) >= 10
    for path in paths:
        assert (ROOT / path).exists(), path


@pytest.mark.parametrize("page", PAGES, ids=lambda p: str(p.relative_to(ROOT)))
def test_commands_are_accepted_by_the_parser(page):
    from exudyn_wheelrail.cli import build_parser
    for command in _commands(page.read_text(encoding="utf-8")):
        words = shlex.split(command)
        if words[:3] == ["python", "-m", "exudyn_wheelrail"] and "--help" not in words:
            try:
                build_parser().parse_args(words[3:])
            except SystemExit as exc:
                pytest.fail(f"{page.name}: {command!r} is rejected by the parser (exit {exc.code})")
        elif words[:1] == ["python"] and words[1:2] and words[1].endswith(".py"):
            assert (ROOT / words[1]).exists(), (page.name, command)


def test_readme_python_blocks_run(tmp_path, monkeypatch, capsys):
    blocks = _blocks(README.read_text(encoding="utf-8"), "python")
    assert len(blocks) >= 2
    monkeypatch.chdir(tmp_path)
    for block in blocks:
        exec(compile(block, "README.md", "exec"), {"__name__": "__readme__"})
    assert capsys.readouterr().out


def test_cli_doc_holds_the_help_of_every_command():
    texts = cli_help_texts()
    blocks = {m.group(1): m.group(2) for m in HELP_BLOCK.finditer(CLI_DOC.read_text(encoding="utf-8"))}
    hint = "regenerate with: python tests/test_docs.py --write-cli"
    assert set(blocks) == set(texts), f"commands without a help block: {sorted(set(texts) - set(blocks))}; {hint}"
    for name, text in texts.items():
        assert blocks[name].split() == text.split(), f"docs/cli.md: the help of {name!r} is not current; {hint}"


def test_cli_doc_has_the_exit_code_section():
    """docs/cli.md's table has a row for every run status with its exit code, and for bad input and other errors,
    as exudyn_wheelrail/simulation/status.py declares them."""
    from exudyn_wheelrail.simulation import status as S
    text = CLI_DOC.read_text(encoding="utf-8")
    assert "## Exit codes and run status" in text
    section = text.split("## Exit codes and run status")[1].split("\n## ")[0]
    rows = {f"| {S.EXIT_CODES[kind]} | `{kind}` |" for kind in S.STATUSES}
    rows |= {f"| {S.EXIT_BAD_INPUT} | — |", f"| {S.EXIT_ERROR} | — |"}
    for row in rows:
        assert row in section, row


@pytest.mark.parametrize("page", PAGES, ids=lambda p: str(p.relative_to(ROOT)))
def test_pages_describe_the_product_not_the_work_on_it(page):
    text = page.read_text(encoding="utf-8")
    found = re.findall(f"(?i){PAGE_WORK_WORDS}", text)
    assert not found, (page.name, found)


def test_source_text_describes_the_product_not_the_work_on_it():
    files = sorted({path for pattern in SOURCE_GLOBS for path in ROOT.glob(pattern)} - {Path(__file__).resolve()})
    assert len(files) > 50
    found = []
    for path in files:
        for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
            found += [f"{path.relative_to(ROOT)}:{number}: {m}" for m in re.findall(f"(?i){WORK_WORDS}", line)]
    assert not found, "\n".join(found)


if __name__ == "__main__":
    if sys.argv[1:] == ["--write-cli"]:
        missing = write_cli_doc()
        print(f"wrote {CLI_DOC}" + (f"; no help block yet for: {', '.join(missing)}" if missing else ""))
    else:
        print("usage: python tests/test_docs.py --write-cli", file=sys.stderr)
        sys.exit(2)
