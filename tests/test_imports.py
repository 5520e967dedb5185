"""The package's import structure: no module imports another that imports it back (at any
depth, counting imports inside functions too), and no private name crosses a package."""
import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "lamodel"


def _module_name(path: Path) -> str:
    parts = list(path.relative_to(ROOT).with_suffix("").parts)
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _modules() -> dict:
    return {_module_name(p): p for p in PACKAGE.rglob("*.py")}


def _imports(name: str, path: Path, known) -> list:
    """(imported module, imported names, line) of every import of lamodel modules in a file."""
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    found = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            found += [(a.name, [], node.lineno) for a in node.names if a.name.split(".")[0] == "lamodel"]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")
                base = base[:len(base) - (node.level - 1)]
                target = ".".join(base + ([node.module] if node.module else []))
            else:
                target = node.module or ""
            if target.split(".")[0] != "lamodel":
                continue
            for alias in node.names:
                sub = f"{target}.{alias.name}"
                if sub in known:  # `from . import module`
                    found.append((sub, [], node.lineno))
                else:
                    found.append((target, [alias.name], node.lineno))
    return found


def import_graph() -> dict:
    known = _modules()
    return {name: {t for t, _, _ in _imports(name, path, known) if t in known and t != name}
            for name, path in known.items()}


def cycles(graph) -> list:
    """The strongly connected components of more than one module (Tarjan)."""
    index, low, stack, on, out = {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in sorted(graph[v]):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))
    for v in sorted(graph):
        if v not in index:
            visit(v)
    return out


def test_the_checker_finds_a_cycle():
    assert cycles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c"]]
    assert cycles({"a": {"b"}, "b": set()}) == []


def test_no_import_cycle_in_the_package():
    assert cycles(import_graph()) == []


def test_no_private_name_is_imported_from_another_package():
    known = _modules()
    crossing = []
    for name, path in known.items():
        here = name if path.name == "__init__.py" else name.rpartition(".")[0]
        for target, names, line in _imports(name, path, known):
            there = target if known.get(target, Path()).name == "__init__.py" else target.rpartition(".")[0]
            private = [n for n in [*names, target.rpartition(".")[2]] if n.startswith("_") and not n.endswith("__")]
            if private and there != here:
                crossing.append(f"{path.relative_to(ROOT)}:{line} imports {', '.join(private)} from {target}")
    assert crossing == []


def test_the_stop_signals_and_the_process_sit_below_the_search():
    """lamodel.signals (where the stop signals are caught) imports nothing of lamodel, and
    lamodel.process only it: the search and the commands lean on them, never the reverse."""
    graph = import_graph()
    assert graph["lamodel.signals"] == set()
    assert graph["lamodel.process"] <= {"lamodel.signals", "lamodel.errors"}


def test_no_module_is_longer_than_a_reader_can_follow():
    """One job per file: none over 450 lines (split by job when one grows past it)."""
    long = {str(p.relative_to(ROOT)): n for p in PACKAGE.rglob("*.py")
            if (n := len(p.read_text(encoding="utf-8").splitlines())) > 450}
    assert long == {}
