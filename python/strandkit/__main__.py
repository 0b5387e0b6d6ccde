"""``python -m strandkit …``: the command line (strandkit.cli)."""
import sys

from .cli import main

sys.exit(main())
