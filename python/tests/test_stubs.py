# SPDX-License-Identifier: LGPL-2.1-only
"""The type hints (nnstreamer/_nnstreamer.pyi) describe what the module really has."""
import ast
import inspect
import pathlib

import nnstreamer
import nnstreamer._nnstreamer as ext

STUB = pathlib.Path(nnstreamer.__file__).with_name("_nnstreamer.pyi")


def stub_tree() -> ast.Module:
    assert STUB.is_file(), f"{STUB} missing"
    return ast.parse(STUB.read_text())


def test_every_public_name_has_a_hint():
    tree = stub_tree()
    names = set()
    for node in tree.body:
        if isinstance(node, (ast.ClassDef, ast.FunctionDef)):
            names.add(node.name)
        elif isinstance(node, ast.AnnAssign):
            names.add(node.target.id)
        elif isinstance(node, ast.Assign):
            names.update(t.id for t in node.targets if isinstance(t, ast.Name))
    public = {n for n in dir(ext) if not n.startswith("__")}
    assert public - names == set(), "names without a hint in the stub"
    assert {n for n in nnstreamer.__all__} <= names


def test_class_members_match():
    for node in stub_tree().body:
        if not isinstance(node, ast.ClassDef) or not hasattr(ext, node.name):
            continue
        cls = getattr(ext, node.name)
        if not inspect.isclass(cls) or issubclass(cls, (tuple, int, BaseException)):
            continue
        hinted = {n.name for n in node.body if isinstance(n, ast.FunctionDef)}
        hinted |= {n.target.id for n in node.body if isinstance(n, ast.AnnAssign)}
        dunders = ("__enter__", "__exit__", "__getitem__", "__setitem__")
        real = {n for n in dir(cls) if not n.startswith("_") or n in dunders}
        assert real - hinted - {"__init__"} == set(), f"{node.name}: members without hints"
        assert hinted - real - {"__init__"} == set(), f"{node.name}: hints of missing members"
