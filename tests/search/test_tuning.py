"""Every tuned number of the search and of the lower bound lives in lamodel/search/tuning.py.

The rule: in ``lamodel/search/`` and ``lamodel/bound/`` a module-level name may be bound to a
value made of number literals alone (a number, arithmetic on numbers, a tuple, list or set of
them, a dict with a number among its values), and a parameter may default to a number other
than 0 and +-1, only in ``tuning.py``. Names, strings and enum-like tables of words
(statuses, method names, signals) are no constants of the search; a formula of other names
(``BETA = sin(pi / (2 ZONES)) ...``) is derived, and its tuned inputs live in ``tuning.py``;
a number inside an expression is the code's own (a round-off guard such as ``1e-300``, a
line search's Armijo factor). Each constant in ``tuning.py`` says why in at most three
lines of comment; its measurements are in ``docs/method/evidence.md``, under its name.
"""
import ast
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
TUNING = ROOT / "lamodel" / "search" / "tuning.py"
EVIDENCE = ROOT / "docs" / "method" / "evidence.md"
#: numbers allowed outside tuning.py: "path:NAME" (a module's constant) or "path:function(parameter)"
#: (a default) -> why
ALLOWED = {
    f"lamodel/search/ga.py:genetic_search({name})": "a general GA's own default; the search and the seed method "
                                                     "pass theirs (Z_MAX, SEED_GENE_MAX, the options' population)"
    for name in ("upper", "pop_size", "generations")}


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


def default_numbers(path: Path) -> list:
    """(function(parameter), line) of every parameter defaulting to a number other than 0, +-1."""
    found = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda)):
            a = node.args
            positional = a.posonlyargs + a.args
            pairs = [*zip(positional[len(positional) - len(a.defaults):], a.defaults),
                     *((arg, d) for arg, d in zip(a.kwonlyargs, a.kw_defaults) if d is not None)]
            name = getattr(node, "name", "lambda")
            found += [(f"{name}({arg.arg})", node.lineno) for arg, d in pairs
                      if _numeric(d) and ast.literal_eval(d) not in (0, 1, -1)]
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
    f.write_text("def f(a, b=2, c=0, d=-1.0, *, e=1e-9, g=True, h=None, k=X):\n    return lambda t=0.5: t\n")
    assert sorted(default_numbers(f)) == [("f(b)", 1), ("f(e)", 1), ("lambda(t)", 2)]


def test_no_constant_of_the_search_outside_tuning():
    found = []
    for folder in ("search", "bound"):
        for path in sorted((ROOT / "lamodel" / folder).rglob("*.py")):
            if path == TUNING:
                continue
            where = path.relative_to(ROOT)
            found += [f"{where}:{line} {name}" for name, line in module_constants(path) + default_numbers(path)
                      if f"{where}:{name}" not in ALLOWED]
    assert found == [], "move these to lamodel/search/tuning.py (one definition each):\n" + "\n".join(found)


def test_every_allowed_number_is_still_there():
    present = {f"{p.relative_to(ROOT)}:{name}" for folder in ("search", "bound")
               for p in (ROOT / "lamodel" / folder).rglob("*.py")
               for name, _ in module_constants(p) + default_numbers(p)}
    assert set(ALLOWED) <= present


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
