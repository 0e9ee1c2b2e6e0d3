"""``docs/transcript.py`` for the tests: the pages fold the transcripts' long lines, ``unfold``
joins them (the docs folder is not a package)."""
import importlib.util
import pathlib

_spec = importlib.util.spec_from_file_location(
    "docs_transcript", pathlib.Path(__file__).resolve().parents[1] / "docs" / "transcript.py")
_mod = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(_mod)
unfold = _mod.unfold
