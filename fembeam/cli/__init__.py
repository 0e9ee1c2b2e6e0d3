"""``fembeam`` command line: ``fembeam <command> --help`` for each command.  The modules
here parse arguments, call one function of the library and print or write its result."""
from .main import build_parser, main

__all__ = ["main", "build_parser"]
