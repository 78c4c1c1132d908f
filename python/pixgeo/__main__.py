"""The ``pixgeo`` command, as ``pip install`` puts it on the PATH (and as
``python -m pixgeo`` runs it): the same command line as the Rust binary,
compiled into the package."""

import sys

from . import _pixgeo


def main() -> None:
    sys.exit(_pixgeo.cli(["pixgeo", *sys.argv[1:]]))


if __name__ == "__main__":
    main()
