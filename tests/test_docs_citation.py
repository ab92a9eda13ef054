"""``splinecontact citation`` / ``--version`` and CITATION.cff name the package version and the paper."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from typer.testing import CliRunner

from splinecontact._version import __version__
from splinecontact.cli import app
from splinecontact.cli._citation import PAPER, citation_text, version_text

ROOT = Path(__file__).resolve().parents[1]
runner = CliRunner()


def _paper_parts(text: str) -> None:
    assert "Hanaor" in text and "Gan" in text and "Einav" in text
    assert "Contact mechanics of fractal surfaces by spline assisted discretisation" in text
    assert "International Journal of Solids and Structures" in text
    assert "59" in text and "2015" in text and re.search(r"121\s*(–|--)\s*131", text)


def test_citation_prints_the_package_version_and_the_paper() -> None:
    result = runner.invoke(app, ["citation"])
    assert result.exit_code == 0, result.output
    assert f"version {__version__}" in result.output
    _paper_parts(result.output)


def test_citation_bibtex_has_both_entries() -> None:
    result = runner.invoke(app, ["citation", "--bibtex"])
    assert result.exit_code == 0, result.output
    out = result.output
    assert out.count("@software{") == 1 and out.count("@article{") == 1
    assert f"version = {{{__version__}}}" in out
    _paper_parts(out)
    assert out.count("{") == out.count("}")  # balanced braces: BibTeX parses


def test_version_option_names_version_and_method() -> None:
    result = runner.invoke(app, ["--version"])
    assert result.exit_code == 0, result.output
    assert result.output.strip() == version_text()
    assert f"splinecontact {__version__}" in result.output
    assert "Hanaor" in result.output


def test_citation_writes_nothing(tmp_path: Path, monkeypatch) -> None:  # type: ignore[no-untyped-def]
    monkeypatch.chdir(tmp_path)
    assert runner.invoke(app, ["citation"]).exit_code == 0
    assert list(tmp_path.iterdir()) == []


def test_citation_cff_matches_the_package() -> None:
    text = (ROOT / "CITATION.cff").read_text(encoding="utf-8")
    assert re.search(r"^cff-version: 1\.2\.0$", text, re.M)
    assert re.search(rf"^version: {re.escape(__version__)}$", text, re.M), (
        f"CITATION.cff version differs from _version.py ({__version__})"
    )
    assert "preferred-citation:" in text and "references:" in text
    assert text.count(f"title: {PAPER['title']}") == 2
    for key in ("volume: 59", "start: 121", "end: 131", "year: 2015", PAPER["journal"]):
        assert key in text
    assert "doi" not in text.lower()  # no DOI stated without a source for it
    assert "\t" not in text  # YAML forbids tabs in indentation


def test_changelog_has_an_entry_for_this_version() -> None:
    text = (ROOT / "CHANGELOG.md").read_text(encoding="utf-8")
    assert re.search(rf"^## {re.escape(__version__)}\b", text, re.M)


def test_citation_text_default_is_text() -> None:
    assert citation_text() == citation_text("text")
    assert "@" not in citation_text()


def test_citation_cff_is_valid_yaml_when_a_parser_is_installed() -> None:
    yaml = pytest.importorskip("yaml")
    data = yaml.safe_load((ROOT / "CITATION.cff").read_text(encoding="utf-8"))
    assert str(data["version"]) == __version__
    assert data["preferred-citation"]["type"] == "article"
    assert [a["family-names"] for a in data["preferred-citation"]["authors"]] == [
        "Hanaor",
        "Gan",
        "Einav",
    ]
    assert data["references"][0]["title"] == data["preferred-citation"]["title"]
