"""The module layout of docs/architecture.md: the analysis modules import each other only at the
top of a module, never a private name, and without a cycle; the other import paths of the moved
names still answer."""
import ast
import pathlib


ANALYSIS = pathlib.Path(__file__).resolve().parents[1] / "fembeam" / "analysis"


def _imports():
    """``{module: [(imported module, name, at top level), ...]}`` of the relative imports."""
    out = {}
    for path in sorted(ANALYSIS.glob("*.py")):
        tree = ast.parse(path.read_text())
        top = {id(node) for node in tree.body}
        found = []
        for node in ast.walk(tree):
            if isinstance(node, ast.ImportFrom) and node.level == 1:
                for alias in node.names:
                    mod = node.module.split(".")[0] if node.module else alias.name
                    found.append((mod, alias.name, id(node) in top))
        out[path.stem] = found
    return out


def test_analysis_modules_form_layers():
    imports = _imports()
    bad = [(m, mod, name) for m, found in imports.items() for mod, name, top in found
           if not top or name.startswith("_")]
    assert not bad, f"imports inside functions or of private names: {bad}"
    graph = {m: {mod for mod, _, _ in found} for m, found in imports.items() if m != "__init__"}
    done: set = set()

    def visit(m, path):
        assert m not in path, f"import cycle {' -> '.join(path + [m])}"
        if m not in done:
            for d in graph.get(m, ()):
                visit(d, path + [m])
            done.add(m)

    for m in graph:
        visit(m, [])
    assert graph["rows"] <= {"lp", "statics"} and "friction" not in graph["limit"]


def test_each_name_is_declared_in_its_own_module_only():
    """The LP rows, the friction checks and the mesh sizes are public in their own modules
    (rows, hinge, sizes), not again in the modules that use them."""
    from fembeam.analysis import friction, limit, pipeline, rows, sizes
    from fembeam.mechanisms import hinge

    for module, home in ((limit, rows), (friction, rows), (friction, hinge), (pipeline, sizes)):
        assert not set(module.__all__) & set(home.__all__), (module.__name__, home.__name__)


def test_the_simulation_has_no_former_names():
    """The former name REST_ENERGY is gone; REST_KINETIC is the one name of the rest threshold."""
    from fembeam.simulation import constants, stepper

    assert not hasattr(stepper, "REST_ENERGY")
    assert stepper.REST_KINETIC is constants.REST_KINETIC
