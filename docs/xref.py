"""Sphinx extension: the cross-references of fembeam's docstrings.

The docstrings name objects as Python would from the module that defines them
(``:func:`frame_rows``` in :mod:`fembeam.output.motion`, ``fembeam.geometry.base.MidCurve``),
while the API reference documents the public names (``fembeam.MidCurve``) and shows parts of
the docstrings on other pages (the summaries of the API index). So:

1. each docstring's references are qualified where they are read (``autodoc-process-docstring``):
   a name found from the docstring's class, module or enclosing packages becomes that full path
   (the text shown stays the docstring's);
2. a full path Sphinx cannot resolve (``missing-reference``) links to where the site documents
   that object under another name; an object of the package that the API reference does not
   document (a helper, a constant, a private function) is shown as code without a link;
3. a name that is no object of the package keeps Sphinx's warning, an error in the nitpicky
   build: a docstring naming something that does not exist fails the build.
"""
from __future__ import annotations

import importlib
import inspect
import re
from typing import Any

MISSING = object()
ROLE = re.compile(r":(func|class|meth|attr|data|obj|mod|exc|const):`(~?)([A-Za-z_.][\w.]*)`")


def _lookup(path: str) -> Any:
    """The object at the dotted ``path`` (a module, or attributes of the longest importable
    module prefix; a dataclass field or annotated name without a value counts as existing:
    ``("field", owner, name)``), or MISSING."""
    parts = path.split(".")
    for i in range(len(parts), 0, -1):
        try:
            obj = importlib.import_module(".".join(parts[:i]))
        except ImportError:
            continue
        for name in parts[i:]:
            nxt = getattr(obj, name, MISSING)
            if nxt is MISSING:
                if name in getattr(obj, "__dataclass_fields__", {}) or name in getattr(obj, "__annotations__", {}):
                    return ("field", obj, name)
                return MISSING
            obj = nxt
        return obj
    return MISSING


def _key(obj: Any):
    """Identity of a module, class, function, method or property (a dataclass field: its class
    and name); None for a value (a constant's identity is not its name's)."""
    if isinstance(obj, tuple) and obj[:1] == ("field",):
        return ("field", id(obj[1]), obj[2])
    if inspect.ismodule(obj) or inspect.isclass(obj) or callable(obj) or isinstance(obj, property):
        return id(obj)
    return None


def _scopes(what: str, name: str, obj: Any) -> list[str]:
    """Dotted scopes in which the docstring of ``obj`` (documented as ``name``) reads names:
    its class, its module and the packages enclosing it."""
    if what == "module":
        module, cls = obj.__name__, None
    elif inspect.isclass(obj):
        module, cls = obj.__module__, f"{obj.__module__}.{obj.__qualname__}"
    else:
        owner = _lookup(name.rsplit(".", 1)[0])
        if inspect.isclass(owner):
            module, cls = owner.__module__, f"{owner.__module__}.{owner.__qualname__}"
        else:
            module, cls = getattr(obj, "__module__", None) or getattr(owner, "__name__", None), None
    if not isinstance(module, str):
        return []
    parts = module.split(".")
    return ([cls] if cls else []) + [".".join(parts[:i]) for i in range(len(parts), 0, -1)]


def qualify(app, what, name, obj, options, lines):
    scopes = _scopes(what, name, obj)
    if not scopes:
        return

    def full(m: re.Match) -> str:
        role, tilde, target = m.groups()
        if target.startswith("fembeam."):
            return m.group(0)
        bare = target.lstrip(".")
        for scope in scopes:
            if _lookup(f"{scope}.{bare}") is not MISSING:
                shown = bare.rsplit(".", 1)[-1] if tilde else target
                return f":{role}:`{shown} <{scope}.{bare}>`"
        return m.group(0)

    lines[:] = [ROLE.sub(full, line) for line in lines]


def _documented(env) -> dict:
    """Identity of every object the site documents -> its documented name."""
    cache = getattr(env, "_fembeam_documented", None)
    if cache is None:
        cache = {}
        for name in sorted(env.get_domain("py").objects, key=len):
            obj = _lookup(name)
            if obj is not MISSING and _key(obj) is not None:
                cache.setdefault(_key(obj), name)
        env._fembeam_documented = cache
    return cache


def resolve(app, env, node, contnode):
    if node.get("refdomain") != "py" or not node["reftarget"].startswith("fembeam"):
        return None
    obj = _lookup(node["reftarget"])
    if obj is MISSING:
        return None
    key = _key(obj)
    name = None if key is None else _documented(env).get(key)
    if name is None:
        return contnode
    return env.get_domain("py").resolve_xref(env, node.get("refdoc"), app.builder, "obj", name, node, contnode)


def setup(app):
    app.connect("autodoc-process-docstring", qualify)
    app.connect("missing-reference", resolve)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
