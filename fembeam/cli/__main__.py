"""``python -m fembeam.cli``: the same as the ``fembeam`` command."""
import sys

from .main import main

sys.exit(main())
