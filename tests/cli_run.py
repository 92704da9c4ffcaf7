"""Running the command line inside the test process."""

from __future__ import annotations

from babyrobot_marl import cli


def run(argv: list[str]) -> int:
    """``cli.main``'s exit status, whether it returns it or argparse raises SystemExit."""
    try:
        return cli.main(argv)
    except SystemExit as exit_:
        return exit_.code if isinstance(exit_.code, int) else 1
