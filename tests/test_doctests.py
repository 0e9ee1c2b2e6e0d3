"""The docstrings of the public API: their Examples run, and their sections are there.

1. ``doctest`` runs the Examples of the modules in :data:`MODULES` (each docstring's under 2 s:
   small voussoir arches, short pulses; outputs printed rounded, stable across BLAS).
2. Every name the API reference lists (``docs/api/index.rst``) has a Parameters section and a
   Returns/Yields section (functions), and a class a Parameters or an Attributes section (a
   class the user builds has its parameters, a result class its attributes), as numpydoc
   parses them (what ``docs/check_site.py --api-strict`` checks on the built site); the
   exceptions need neither.
3. Every entry point and every result class has an Examples section with a doctest, in a
   module of :data:`MODULES` (so that 1. runs it): the names of the API reference (but the
   exceptions) and the ``run`` method of its classes, every class named ``*Result`` in the
   ``__all__`` of a module of the package, and the results of :data:`RESULTS`.
"""
from __future__ import annotations

import doctest
import importlib
import inspect
import pkgutil
import re
import time
import warnings
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent

# the modules whose docstrings have Examples
MODULES = [
    "fembeam.analysis.pipeline",
    "fembeam.analysis.qp",
    "fembeam.analysis.limit",
    "fembeam.analysis.impact",
    "fembeam.analysis.thickness",
    "fembeam.analysis.thrust_range",
    "fembeam.analysis.continuum",
    "fembeam.analysis.supports",
    "fembeam.geometry.base",
    "fembeam.geometry.circular",
    "fembeam.geometry.pointed",
    "fembeam.geometry.elliptical",
    "fembeam.geometry.parabolic",
    "fembeam.geometry.catenary",
    "fembeam.geometry.surveyed",
    "fembeam.geometry.block",
    "fembeam.fem.rigid",
    "fembeam.fem.mesh",
    "fembeam.mechanisms.hinge",
    "fembeam.mechanisms.mechanism",
    "fembeam.mechanisms.energy",
    "fembeam.mechanisms.classical",
    "fembeam.mechanisms.restricted",
    "fembeam.mechanisms.four_hinge_analysis",
    "fembeam.dynamics.ground",
    "fembeam.dynamics.equation",
    "fembeam.dynamics.transitions",
    "fembeam.dynamics.rocking",
    "fembeam.dynamics.result",
    "fembeam.auto.model",
    "fembeam.auto.manifold",
    "fembeam.simulation.stepper",
    "fembeam.simulation.projection",
    "fembeam.simulation.result",
    "fembeam.studies.collapse",
    "fembeam.studies.assess",
    "fembeam.studies.suites",
    "fembeam.studies.intensity",
    "fembeam.studies.convergence",
    "fembeam.studies.sweep",
    "fembeam.studies.spectrum",
    "fembeam.studies.huntfill",
    "fembeam.studies.lognormal",
    "fembeam.studies.load_scan",
    "fembeam.studies.models",
    "fembeam.studies.fragility",
    "fembeam.output.export",
    "fembeam.output.plotting",
    "fembeam.output.render",
    "fembeam.output.motion",
]

# the results of public functions whose class is not named *Result (those are found in the
# __all__ lists: :func:`result_classes`)
RESULTS = [
    "fembeam.analysis.thickness.MinimumThickness",
    "fembeam.analysis.thrust_range.ThrustRange",
    "fembeam.analysis.continuum.ContinuumLimit",
    "fembeam.dynamics.result.ImpactEvent",
    "fembeam.dynamics.transitions.Transition",
    "fembeam.auto.model.Segment",
    "fembeam.mechanisms.energy.ImpactFigures",
    "fembeam.mechanisms.four_hinge_analysis.FourHingeImpact",
    "fembeam.studies.convergence.ConvergenceStudy",
    "fembeam.studies.intensity.IntensityMeasure",
    "fembeam.studies.lognormal.LognormalFit",
    "fembeam.studies.load_scan.LoadScan",
    "fembeam.studies.suites.Record",
    "fembeam.studies.suites.Suite",
]

# docstring examples are written to take under 2 s on an idle machine; one slower than this
# is reported as a warning (not a failure: no test depends on the machine's speed)
SLOW_S = 5.0


@pytest.mark.parametrize("module", MODULES)
def test_examples_run(module):
    mod = importlib.import_module(module)
    finder = doctest.DocTestFinder()
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    tests = [t for t in finder.find(mod, module) if t.examples]
    assert tests, f"{module} has no Examples"
    slow = []
    for test in tests:
        t0 = time.perf_counter()
        runner.run(test)
        if (dt := time.perf_counter() - t0) > SLOW_S:
            slow.append(f"{test.name}: {dt:.1f} s")
    result = runner.summarize(verbose=False)
    assert result.failed == 0, f"{result.failed} of {result.attempted} examples of {module} failed"
    if slow:
        warnings.warn(f"examples slower than {SLOW_S} s of wall time: " + ", ".join(slow), stacklevel=1)


def api_names() -> list[str]:
    """The full names the API reference lists (its autosummary entries)."""
    names, module = [], None
    for line in (ROOT / "docs" / "api" / "index.rst").read_text(encoding="utf-8").splitlines():
        if m := re.match(r"\.\. currentmodule:: (\S+)", line):
            module = m.group(1)
        elif (m := re.match(r" {3}([A-Za-z_][\w.]*)$", line)) and module:
            names.append(f"{module}.{m.group(1)}")
    return names


def resolve(name: str):
    """The object ``name`` names, as autodoc finds it: each part an attribute of the one before,
    a submodule imported only where there is no such attribute (``fembeam.studies.sweep`` is the
    function the package exports, not the module of that name)."""
    parts = name.split(".")
    obj = importlib.import_module(parts[0])
    for i, part in enumerate(parts[1:], 2):
        try:
            obj = getattr(obj, part)
        except AttributeError:
            obj = importlib.import_module(".".join(parts[:i]))
    return obj


def missing_sections(obj) -> list[str]:
    """The sections ``obj``'s docstring lacks, as numpydoc (the docs extra) parses it."""
    numpydoc_docscrape = pytest.importorskip("numpydoc.docscrape")
    if inspect.isclass(obj) and issubclass(obj, BaseException):
        return []       # an exception: its message says it all
    if inspect.isclass(obj):
        doc = numpydoc_docscrape.ClassDoc(obj, config={"show_class_members": False})
        need = {"Parameters or Attributes": doc["Parameters"] or doc["Attributes"]}
    else:
        doc = numpydoc_docscrape.FunctionDoc(obj)
        need = {"Parameters": doc["Parameters"], "Returns": doc["Returns"] or doc["Yields"]}
    return [k for k, v in need.items() if not v]


def test_api_listed():
    names = api_names()
    assert len(names) > 50 and "fembeam.analyze" in names


@pytest.mark.parametrize("name", api_names())
def test_api_sections(name):
    missing = missing_sections(resolve(name))
    assert not missing, f"{name}: no {' and no '.join(missing)} section"


def result_classes() -> list[str]:
    """The full names (where defined) of the classes named ``*Result`` in the ``__all__`` of a
    module of the package (the command line's modules aside)."""
    import fembeam

    found = set()
    for info in pkgutil.walk_packages(fembeam.__path__, "fembeam."):
        if info.name.startswith("fembeam.cli") or info.name.endswith("__main__"):
            continue
        mod = importlib.import_module(info.name)
        for name in getattr(mod, "__all__", ()):
            obj = getattr(mod, name, None)
            if inspect.isclass(obj) and name.endswith("Result"):
                found.add(f"{obj.__module__}.{obj.__qualname__}")
    return sorted(found)


def locate(name: str):
    """The object ``name`` names where it is defined: the longest module its parts name, then
    its attributes (``fembeam.analysis.impact.ImpactResult`` is the class of the module
    ``fembeam.analysis.impact``, not an attribute of the function ``fembeam.analysis.impact``
    that :func:`resolve` finds first)."""
    parts = name.split(".")
    for i in range(len(parts), 0, -1):
        try:
            obj = importlib.import_module(".".join(parts[:i]))
        except ModuleNotFoundError:
            continue
        for part in parts[i:]:
            obj = getattr(obj, part)
        return obj
    raise ImportError(name)


def example_objects() -> dict:
    """The entry points and result classes whose docstrings must have Examples, by full name:
    the API reference's names but the exceptions (as :func:`resolve` finds them), the ``run``
    method of its classes, the ``*Result`` classes of the ``__all__`` lists and :data:`RESULTS`
    (as :func:`locate` finds them); each object once."""
    found, seen = {}, set()

    def add(name, obj):
        if id(obj) not in seen:
            found[name] = obj
            seen.add(id(obj))

    for name in api_names():
        obj = resolve(name)
        if inspect.isclass(obj) and issubclass(obj, BaseException):
            continue
        add(name, obj)
        if inspect.isclass(obj) and inspect.isfunction(getattr(obj, "run", None)):
            add(f"{name}.run", obj.run)
    for name in result_classes() + RESULTS:
        add(name, locate(name))
    return found


EXAMPLES = example_objects()


def test_examples_listed():
    assert "fembeam.simulation.Simulator.run" in EXAMPLES and "fembeam.dynamics.RockingResult" in EXAMPLES
    assert "fembeam.analysis.supports.SupportsResult" in EXAMPLES and len(EXAMPLES) > 70


@pytest.mark.parametrize("name", EXAMPLES)
def test_api_examples(name):
    obj = EXAMPLES[name]
    doc = inspect.getdoc(obj) or ""
    m = re.search(r"^Examples\n-{8,}\n(.*?)(?=^\S[^\n]*\n-{3,}\n|\Z)", doc, re.M | re.S)
    assert m, f"{name}: no Examples section"
    assert ">>> " in m.group(1), f"{name}: its Examples run no code"
    module = inspect.unwrap(obj).__module__
    assert module in MODULES, f"{name}: its module {module} is not in MODULES, its examples do not run"
