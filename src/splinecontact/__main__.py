"""``python -m splinecontact``: the command line."""

from .cli import main

main()
