"""Sub-commands of the ``fembeam`` CLI; each module has ``register(subparsers)``."""
