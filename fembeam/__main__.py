"""``python -m fembeam``: the same as the ``fembeam`` command."""
import sys

from .cli.main import main

sys.exit(main())
