"""``python -m flexmbd.cli``: the ``flexmbd`` command."""

import sys

from . import main

if __name__ == "__main__":  # a study's worker processes import this module again
    sys.exit(main())
