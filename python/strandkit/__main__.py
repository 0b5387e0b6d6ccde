"""``python -m strandkit …``: the command line (strandkit.cli)."""
import sys

from .cli import main

if __name__ == "__main__":
    sys.exit(main())
