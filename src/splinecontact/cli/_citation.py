"""``splinecontact citation`` and ``splinecontact --version``: what to cite, which version.

Both name the package with its version (``splinecontact._version``) and the paper whose method
it implements. The same two references are in the repository's ``CITATION.cff``.
"""

from __future__ import annotations

from typing import Annotated, Literal

import typer

from .._version import __version__

__all__ = ["PAPER", "citation_text", "register", "version_text"]

#: The paper whose method the package implements (fields of its reference list entry).
PAPER: dict[str, str] = {
    "authors": "Hanaor, D. A. H.; Gan, Y.; Einav, I.",
    "title": "Contact mechanics of fractal surfaces by spline assisted discretisation",
    "journal": "International Journal of Solids and Structures",
    "volume": "59",
    "year": "2015",
    "pages": "121–131",
}

_PACKAGE_TITLE = (
    "splinecontact: contact mechanics of rough surfaces by spline assisted discretization"
)


def version_text() -> str:
    """One line with the package version and the method's reference."""
    return (
        f"splinecontact {__version__} — method of Hanaor, Gan & Einav, "
        f"{PAPER['journal']} {PAPER['volume']} ({PAPER['year']}) {PAPER['pages']}"
    )


def citation_text(style: Literal["text", "bibtex"] = "text") -> str:
    """The two references (the package at this version, and the paper) as text or BibTeX."""
    if style == "bibtex":
        return (
            "@software{splinecontact,\n"
            "  author  = {{splinecontact developers}},\n"
            f"  title   = {{{_PACKAGE_TITLE}}},\n"
            f"  version = {{{__version__}}},\n"
            "  license = {MIT},\n"
            "}\n"
            "\n"
            "@article{hanaor2015,\n"
            "  author  = {Hanaor, Dorian A. H. and Gan, Yixiang and Einav, Itai},\n"
            f"  title   = {{{PAPER['title']}}},\n"
            f"  journal = {{{PAPER['journal']}}},\n"
            f"  volume  = {{{PAPER['volume']}}},\n"
            f"  pages   = {{{PAPER['pages'].replace('–', '--')}}},\n"
            f"  year    = {{{PAPER['year']}}},\n"
            "}\n"
        )
    return (
        "If you use splinecontact, please cite the software version you used and the method:\n"
        "\n"
        f"  splinecontact developers. {_PACKAGE_TITLE}, version {__version__}. "
        "Software, MIT licence.\n"
        "\n"
        f"  {PAPER['authors']} ({PAPER['year']}). {PAPER['title']}. "
        f"{PAPER['journal']} {PAPER['volume']}, {PAPER['pages']}.\n"
        "\n"
        "BibTeX: splinecontact citation --bibtex\n"
    )


def citation(
    bibtex: Annotated[
        bool, typer.Option("--bibtex", help="Print BibTeX entries instead of text.")
    ] = False,
) -> None:
    """Print how to cite splinecontact (this version) and the paper of its method."""
    typer.echo(citation_text("bibtex" if bibtex else "text"), nl=False)


def _version_callback(value: bool) -> None:
    if value:
        typer.echo(version_text())
        raise typer.Exit()


def _main_options(
    version: Annotated[
        bool,
        typer.Option(
            "--version",
            help="Print the version (and the method's reference) and exit.",
            callback=_version_callback,
            is_eager=True,
        ),
    ] = False,
) -> None:
    """Contact mechanics of rough surfaces by spline assisted discretization (SAD)."""


def register(app: typer.Typer) -> None:
    """Add ``citation`` (and ``--version``, unless the app already has a main callback)."""
    app.command("citation")(citation)
    if app.registered_callback is None:
        app.callback()(_main_options)
