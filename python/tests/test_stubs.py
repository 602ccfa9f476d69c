"""The type stubs (cdkit/__init__.pyi) cover the module: every public name of the extension is declared there, every
public attribute of each bound class is declared in its stub class, and every function and class has a docstring."""
import ast
import pathlib

import cdkit

STUB = pathlib.Path(cdkit.__file__).with_name("__init__.pyi")


def stub_names():
    tree = ast.parse(STUB.read_text())
    top, members, bases = set(), {}, {}
    for node in tree.body:
        if isinstance(node, (ast.FunctionDef, ast.ClassDef)):
            top.add(node.name)
        elif isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
            top.add(node.target.id)
        elif isinstance(node, ast.Assign):
            top.update(t.id for t in node.targets if isinstance(t, ast.Name))
        if isinstance(node, ast.ClassDef):
            names = set()
            for item in node.body:
                if isinstance(item, ast.FunctionDef):
                    names.add(item.name)
                elif isinstance(item, ast.AnnAssign) and isinstance(item.target, ast.Name):
                    names.add(item.target.id)
                elif isinstance(item, ast.Assign):
                    names.update(t.id for t in item.targets if isinstance(t, ast.Name))
            members[node.name] = names
            bases[node.name] = [b.id for b in node.bases if isinstance(b, ast.Name)]

    def inherited(name):
        out = set(members.get(name, ()))
        for b in bases.get(name, ()):
            out |= inherited(b)
        return out

    return top, {name: inherited(name) for name in members}


def public(obj):
    return {n for n in dir(obj) if not n.startswith("_")}


def test_stub_ships_beside_the_module():
    assert STUB.exists(), STUB
    assert STUB.with_name("py.typed").exists()


def test_every_bound_name_is_in_the_stub():
    top, members = stub_names()
    missing = sorted(public(cdkit._extension) - top)
    assert not missing, f"not in {STUB.name}: {missing}"
    extra = sorted(n for n in top if not n.startswith("_") and n not in public(cdkit._extension)
                   and n not in ("ArrayLike", "Pose", "Shape"))
    assert not extra, f"in {STUB.name} but not bound: {extra}"
    for name in public(cdkit._extension):
        obj = getattr(cdkit, name)
        if isinstance(obj, type) and name in members:
            if issubclass(obj, BaseException):
                continue  # cdkit.Error: the built-in exception's members
            attrs = public(obj) - {"name", "value"}  # enums' built-ins
            gaps = sorted(attrs - members[name])
            assert not gaps, f"{name}: not in the stub class: {gaps}"


def test_docstrings():
    undocumented = []
    for name in public(cdkit._extension):
        obj = getattr(cdkit, name)
        if callable(obj) and not (obj.__doc__ or "").strip():
            undocumented.append(name)
    assert not undocumented, undocumented
