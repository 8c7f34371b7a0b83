"""The type stubs cover the module: the generated part (enums, error classes) is what the
built module has, and every public name of the package is declared."""

from __future__ import annotations

import ast
import pathlib
import sys

import motioncard as mc

PY = pathlib.Path(__file__).resolve().parents[1]
STUB = PY / "motioncard" / "__init__.pyi"
sys.path.insert(0, str(PY / "tools"))

import stubs  # noqa: E402


def declared() -> dict[str, ast.AST]:
    tree = ast.parse(STUB.read_text())
    out: dict[str, ast.AST] = {}
    for node in tree.body:
        if isinstance(node, (ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)):
            out[node.name] = node
        elif isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
            out[node.target.id] = node
        elif isinstance(node, ast.Assign):
            for t in node.targets:
                if isinstance(t, ast.Name):
                    out[t.id] = node
    return out


def test_generated_part_is_current() -> None:
    text = STUB.read_text()
    assert stubs.stub_with(text, stubs.generated()) == text, "run python/tools/stubs.py"


def test_every_public_name_is_declared() -> None:
    d = declared()
    missing = [n for n in mc.__all__ if n not in d]
    assert missing == []


def test_every_public_method_is_declared() -> None:
    d = declared()
    for name in mc.__all__:
        obj = getattr(mc, name)
        node = d[name]
        if not isinstance(obj, type) or not isinstance(node, ast.ClassDef):
            continue
        if issubclass(obj, (mc.Error, int)):
            continue
        members = {
            n.name if isinstance(n, (ast.FunctionDef, ast.AsyncFunctionDef)) else
            n.target.id if isinstance(n, ast.AnnAssign) and isinstance(n.target, ast.Name) else ""
            for n in node.body
        }
        public = {m for m in vars(obj) if not m.startswith("_")}
        assert public - members == set(), name
        for dunder in ("__enter__", "__exit__", "__iter__", "__next__", "__await__", "__aiter__"):
            if dunder in vars(obj):
                assert dunder in members, (name, dunder)
