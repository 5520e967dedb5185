"""Every tuned number of the search and of the lower bound lives in lamodel/search/tuning.py.

The rule: in ``lamodel/search/`` and ``lamodel/bound/`` a module-level name may be bound to a
value made of number literals alone (a number, arithmetic on numbers, a tuple, list or set of
them, a dict with a number among its values) only in ``tuning.py``. Names, strings and
enum-like tables of words (statuses, method names, signals) are no constants of the search;
a formula of other names (``BETA = sin(pi / (2 ZONES)) ...``) is derived, and its tuned
inputs live in ``tuning.py``. Each constant there says why in at most three lines of
comment; its measurements are in ``docs/method/evidence.md``, under its name.
"""
import ast
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
TUNING = ROOT / "lamodel" / "search" / "tuning.py"
EVIDENCE = ROOT / "docs" / "method" / "evidence.md"
#: module-level numbers allowed outside tuning.py: "path:NAME" -> why (none needed so far)
ALLOWED: dict = {}


def _numeric(node) -> bool:
    """A value of number literals alone, with at least one number."""
    if isinstance(node, ast.Constant):
        return isinstance(node.value, (int, float, complex)) and not isinstance(node.value, bool)
    if isinstance(node, ast.UnaryOp):
        return _numeric(node.operand)
    if isinstance(node, ast.BinOp):
        return _literal(node.left) and _literal(node.right) and (_numeric(node.left) or _numeric(node.right))
    if isinstance(node, (ast.Tuple, ast.List, ast.Set)):
        return all(map(_literal, node.elts)) and any(map(_numeric, node.elts))
    if isinstance(node, ast.Dict):
        return any(v is not None and _numeric(v) for v in node.values)
    return False


def _literal(node) -> bool:
    if isinstance(node, ast.Constant):
        return True
    if isinstance(node, ast.UnaryOp):
        return _literal(node.operand)
    if isinstance(node, ast.BinOp):
        return _literal(node.left) and _literal(node.right)
    if isinstance(node, (ast.Tuple, ast.List, ast.Set)):
        return all(map(_literal, node.elts))
    return False


def _bindings(node):
    """(target names, value) of a module-level assignment, tuples unpacked pairwise."""
    targets = node.targets if isinstance(node, ast.Assign) else [node.target]
    for target in targets:
        if isinstance(target, ast.Tuple) and isinstance(node.value, ast.Tuple) \
                and len(target.elts) == len(node.value.elts):
            yield from ((t.id, v) for t, v in zip(target.elts, node.value.elts) if isinstance(t, ast.Name))
        elif isinstance(target, ast.Name):
            yield target.id, node.value


def module_constants(path: Path) -> list:
    """(name, line) of every module-level numeric constant in a file."""
    found = []
    for node in ast.parse(path.read_text(encoding="utf-8")).body:
        if isinstance(node, (ast.Assign, ast.AnnAssign)) and node.value is not None:
            found += [(name, node.lineno) for name, value in _bindings(node) if _numeric(value)]
    return found


def _tuning_comments() -> dict:
    """constant names -> the lines of the ``#:`` comment above them in tuning.py (constants
    on consecutive lines share one)."""
    out, block, after = {}, [], False
    for line in TUNING.read_text(encoding="utf-8").splitlines():
        if line.startswith("#:"):
            block, after = (block if not after else []) + [line], False
            continue
        m = re.match(r"([A-Z_][A-Z0-9_]*(?:, *[A-Z_][A-Z0-9_]*)*) *=", line)
        if m:
            out[m.group(1)], after = block, True
        elif not line.startswith((" ", "}", "#")):
            block, after = [], False
    return out


def test_the_checker_sees_numbers_and_only_numbers(tmp_path):
    f = tmp_path / "m.py"
    f.write_text("A = 1e-9\nB, C = 2, 'x'\nD: float = -1.0\nE = (1, 2.0)\nF = {'tol': 1e-8}\n"
                 "G = ('a', 'b')\nH = x * 2\nI = {0: 'ok'}\nJ = 2 ** 10\nK = True\n")
    assert module_constants(f) == [("A", 1), ("B", 2), ("D", 3), ("E", 4), ("F", 5), ("J", 9)]


def test_no_constant_of_the_search_outside_tuning():
    found = []
    for folder in ("search", "bound"):
        for path in sorted((ROOT / "lamodel" / folder).rglob("*.py")):
            if path == TUNING:
                continue
            where = path.relative_to(ROOT)
            found += [f"{where}:{line} {name}" for name, line in module_constants(path)
                      if f"{where}:{name}" not in ALLOWED]
    assert found == [], "move these to lamodel/search/tuning.py (one definition each):\n" + "\n".join(found)


def test_each_constant_is_defined_once_in_tuning():
    names = [name for name, _ in module_constants(TUNING)]
    assert len(names) > 50
    assert sorted({n for n in names if names.count(n) > 1}) == []


def test_each_tuning_comment_is_at_most_three_lines():
    comments = _tuning_comments()
    assert comments, "no #: comment found in tuning.py"
    long = {name: len(lines) for name, lines in comments.items() if len(lines) > 3}
    assert long == {}, f"move the measurements to {EVIDENCE.relative_to(ROOT)}: {long}"
    bare = [name for name, lines in comments.items() if not lines]
    assert bare == [], f"constants without a why: {bare}"


def test_the_evidence_page_is_keyed_by_constants_that_exist():
    names = {name for node in ast.parse(TUNING.read_text(encoding="utf-8")).body
             if isinstance(node, ast.Assign) for name, _ in _bindings(node)}
    keys = re.findall(r"^#{2,4} .*$", EVIDENCE.read_text(encoding="utf-8"), re.MULTILINE)
    cited = {word for key in keys for word in re.findall(r"`([A-Z_][A-Z0-9_]*)`", key)}
    assert len(cited) >= 20
    assert cited - names == set(), f"evidence.md headings name constants not in tuning.py: {cited - names}"
