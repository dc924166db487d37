"""``python -m mrexplore`` runs the command-line interface."""

from mrexplore.cli import console_main

console_main()
