"""Pyomo .dat files of block assemblies: read into a Structure, write from one.

The file is plain Pyomo data for :func:`lamodel.formulation.model.create_abstract_model`::

    set BLOCKS := b1 b2 ;
    set SUPPORTS := ground ;
    set CONTACTS := c1 c2 c3 ;
    param: x y dead_x dead_y live_x live_y :=
      b1 1.0 0.875 0.0 -0.5 0.5 0.0
      ... ;
    param: block_a block_b cx cy nx ny d mu :=
      c1 ground b1 1.0 0.0 0.0 1.0 1.0 0.65
      ... ;
    param: VERTICES: vx vy :=      # optional: block outlines, for pictures only
      b1 1 0.0 0.0
      ... ;
    param: fc :=                   # optional: the joints' strengths, per contact
      c1 5000.0                    # (fc, ft, cohesion, thickness; a contact not listed
      ... ;                        # keeps the default: inf, 0, 0, 1)

so ``create_abstract_model().create_instance('wall33.dat')`` and :func:`read_dat` see the
same data. :func:`read_dat` adds the checks a user needs: every parameter present exactly
once, contacts naming known bodies, unit normals, d > 0, mu >= 0, finite numbers. Stresses
(fc, ft, cohesion) are in the file's force per length squared, as its other numbers.
"""
from __future__ import annotations

import codecs
import contextlib
import math
import os
import re
import tempfile
from collections import defaultdict

import numpy as np

from ..errors import InputError
from ..structure import BLOCK_MOMENT_PARAMS, BLOCK_PARAMS, CONTACT_PARAMS, JOINT_DEFAULTS, STRENGTH_PARAMS, Structure
from .files import atomic_write_text, read_text


def _schema():
    """The sets and parameters a .dat file may hold, as a Pyomo model without constraints:
    Pyomo's reader needs their declarations (the dimension of VERTICES) to parse rows."""
    from pyomo.environ import AbstractModel, Any, Param, Set
    m = AbstractModel(name="lamodel data")
    for name in ("BLOCKS", "SUPPORTS", "CONTACTS"):
        m.add_component(name, Set(dimen=1, ordered=True))
    m.VERTICES = Set(dimen=2, ordered=True)
    for name in BLOCK_PARAMS + BLOCK_MOMENT_PARAMS:
        m.add_component(name, Param(m.BLOCKS, within=Any))
    for name in CONTACT_PARAMS + STRENGTH_PARAMS:
        m.add_component(name, Param(m.CONTACTS, within=Any))
    m.vx = Param(m.VERTICES, within=Any)
    m.vy = Param(m.VERTICES, within=Any)
    return m


def _fmt(v: float) -> str:
    return repr(float(v))


def write_dat(structure: Structure, path) -> str:
    """Write the structure as a Pyomo .dat file (atomically: a temporary file, then rename)."""
    s = structure
    lines = [f"# lamodel instance '{s.name}': {s.n_blocks} blocks, {s.n_contacts} contacts",
             "# conventions: lamodel/structure.py (n from block_a to block_b; N <= 0 is compression)",
             "set BLOCKS := " + " ".join(s.blocks) + " ;",
             "set SUPPORTS := " + " ".join(s.supports) + " ;",
             "set CONTACTS := " + " ".join(s.contacts) + " ;",
             "",
             "param: " + " ".join(BLOCK_PARAMS) + " :="]
    for j, b in enumerate(s.blocks):
        vals = (*s.centroid[j], *s.dead[j], *s.live[j])
        lines.append(f"  {b} " + " ".join(_fmt(v) for v in vals))
    lines.append(";")
    if np.any(s.dead_m) or np.any(s.live_m):  # optional table: files without it stay as before
        lines += ["", "# moments of the loads about the centroids (point loads), default 0",
                  "param: " + " ".join(BLOCK_MOMENT_PARAMS) + " :="]
        lines += [f"  {b} {_fmt(s.dead_m[j])} {_fmt(s.live_m[j])}" for j, b in enumerate(s.blocks)]
        lines.append(";")
    lines += ["", "param: " + " ".join(CONTACT_PARAMS) + " :="]
    for k, c in enumerate(s.contacts):
        vals = (*s.centre[k], *s.normal[k], s.d[k], s.mu[k])
        lines.append(f"  {c} {s.block_a[k]} {s.block_b[k]} " + " ".join(_fmt(v) for v in vals))
    lines.append(";")
    for name in STRENGTH_PARAMS:  # optional tables: the contacts off the default only
        values = getattr(s, name)
        off = np.flatnonzero(values != JOINT_DEFAULTS[name])
        if off.size:
            lines += ["", f"param: {name} :="] + [f"  {s.contacts[k]} {_fmt(values[k])}" for k in off] + [";"]
    if s.polygons:
        lines += ["", "param: VERTICES: vx vy :="]
        for body, verts in s.polygons.items():
            for i, (vx, vy) in enumerate(verts, start=1):
                lines.append(f"  {body} {i} {_fmt(vx)} {_fmt(vy)}")
        lines.append(";")
    atomic_write_text(path, "\n".join(lines) + "\n")
    return str(path)


def _scan_duplicates(path: str, text: str):
    """Pyomo keeps the last of two rows with the same key; a user deserves an error."""
    header = None
    seen = {}
    for lineno, raw in enumerate(text.splitlines(), start=1):
        line = raw.split("#", 1)[0].strip()
        if not line:
            continue
        m = re.match(r"param\s*:(.*):=\s*(.*)$", line)
        if m:
            header, seen = m.group(1), {}
            rest = m.group(2)
            if not rest.strip():
                continue
            line = rest
        if header is None:
            continue
        body = line.rstrip(";").strip()
        if body:
            key = tuple(body.split()[: 2 if header.strip().startswith("VERTICES") else 1])
            if key in seen:
                names = header.replace(":", " ").split()
                raise InputError(f"{path}, line {lineno}: '{' '.join(key)}' is given twice in the table of "
                                 f"{', '.join(names)} (first on line {seen[key]}); expected one row per key")
            seen[key] = lineno
        if line.endswith(";"):
            header = None
    for lineno, raw in enumerate(text.splitlines(), start=1):
        m = re.match(r"\s*set\s+(\w+)\s*:=(.*)", raw.split("#", 1)[0])
        if m:
            members = m.group(2).replace(";", " ").split()
            dup = {x for x in members if members.count(x) > 1}
            if dup:
                raise InputError(f"{path}, line {lineno}: set {m.group(1)} lists '{sorted(dup)[0]}' twice; expected unique ids")


def _scan_row_widths(path: str, text: str):
    """Pyomo silently drops a trailing value too many, or shifts every following row by
    one; a user deserves an error naming the row. A table whose number of values is a
    multiple of its row width is accepted (rows may be wrapped over lines, or share one);
    its rows cut so, a key given twice is an error too (Pyomo keeps the last)."""
    header, rows = None, []

    def check():
        names = header.replace(":", " ").split()  # an indexed table ('VERTICES: vx vy') has a 2-part key
        width = len(names) + 1
        values = names[1:] if header.strip().startswith("VERTICES") else names
        if sum(len(t) for _, t in rows) % width:
            lineno, tokens = next(((n, t) for n, t in rows if len(t) != width), rows[-1])
            raise InputError(f"{path}, line {lineno}: row '{' '.join(tokens[:width - len(values)])}' of the table of "
                             f"{', '.join(values)} has {len(tokens)} entries; expected {width} "
                             "(the key and one value per column)")
        cells, seen = [(n, t) for n, tokens in rows for t in tokens], {}
        for r in range(0, len(cells), width):
            key = tuple(t for _, t in cells[r:r + width - len(values)])
            if key in seen:
                raise InputError(f"{path}, line {cells[r][0]}: '{' '.join(key)}' is given twice in the table of "
                                 f"{', '.join(values)} (first on line {seen[key]}); expected one row per key")
            seen[key] = cells[r][0]

    for lineno, raw in enumerate(text.splitlines(), start=1):
        line = raw.split("#", 1)[0].strip()
        m = re.match(r"param\s*:(.*):=\s*(.*)$", line)
        if m:
            header, rows, line = m.group(1), [], m.group(2).strip()
        if header is None or not line:
            continue
        body = line.split(";", 1)[0].split()
        if body:
            rows.append((lineno, body))
        if ";" in line:
            if rows:
                check()
            header = None


def _unknown_name(path: str, text: str, name: str) -> str:
    """The message for data given to a parameter the model does not declare."""
    where = path
    for lineno, raw in enumerate(text.splitlines(), start=1):
        line = raw.split("#", 1)[0]
        declared = line.split(":=")[0]
        if line.strip().startswith("param") and re.search(rf"(?<![\w.]){re.escape(name)}(?![\w.])", declared):
            where = f"{path}, line {lineno}"
            break
    known = ", ".join((*BLOCK_PARAMS, *BLOCK_MOMENT_PARAMS, *CONTACT_PARAMS, *STRENGTH_PARAMS, "vx", "vy"))
    return f"{where}: unknown parameter '{name}'; expected only the parameters {known}"


@contextlib.contextmanager
def _plain_copy(path, text):
    """The file for Pyomo's parser, which reads it again itself: a UTF-8 copy without the
    byte-order mark when the file has one (Pyomo takes the mark for a token)."""
    with open(path, "rb") as fh:
        if fh.read(3) != codecs.BOM_UTF8:
            yield path
            return
    with tempfile.TemporaryDirectory(prefix="lamodel-dat-") as tmp:
        copy = os.path.join(tmp, os.path.basename(path))
        with open(copy, "w", encoding="utf-8") as fh:
            fh.write(text)
        yield copy


_TOKEN_INT = re.compile(r"[+-]?\d+$")
_STATEMENT = re.compile(r"(set)\s+(\w+)\s*:=(.*)$|(param)\s*:\s*(VERTICES\s*:)?([\w\s]*):=(.*)$", re.S)


def _value(token: str):
    """A data token as Pyomo reads it: an int, a float, else the string."""
    if _TOKEN_INT.match(token):
        return int(token)
    try:
        return float(token)
    except ValueError:
        return token


def _plain_data(text: str):
    """The data of a .dat file written in the plain subset lamodel writes (``set NAME :=
    ids ;``, ``param: NAMES := rows ;``, ``param: VERTICES: vx vy := rows ;``, ``#``
    comments), as a dict like Pyomo's DataPortal; None for anything else, which Pyomo's
    own parser then reads. Same values as Pyomo's (tested on every instance; ids that look
    like numbers stay strings here, which Pyomo's reader turns into numbers and then
    loses); it spares importing Pyomo (about a second) on the command line's path."""
    body = "\n".join(line.split("#", 1)[0] for line in text.splitlines())
    if '"' in body or "'" in body or "[" in body or "(" in body:
        return None
    data = {}
    statements = body.split(";")
    if statements[-1].strip():
        return None  # a statement without its ';'
    for stmt in statements[:-1]:
        stmt = stmt.strip()
        if not stmt:
            continue
        m = _STATEMENT.match(stmt)
        if m is None:
            return None
        if m.group(1):
            name, members = m.group(2), m.group(3).split()  # ids stay strings, also '1'
            if name in data:
                return None
            data[name] = members
            continue
        vertices, names, tokens = bool(m.group(5)), m.group(6).split(), m.group(7).split()
        key_width = 2 if vertices else 1
        width = key_width + len(names)
        if not names or len(tokens) % width or any(n in data for n in names):
            return None
        tables = {n: {} for n in names}
        for r in range(0, len(tokens), width):
            row = tokens[r:r + key_width] + [_value(x) for x in tokens[r + key_width:r + width]]
            key = (row[0], int(row[1])) if vertices else row[0]
            for n, v in zip(names, row[key_width:]):
                if v != ".":  # Pyomo's "no value"
                    tables[n][key] = v
        data.update(tables)
    return data


def read_dat(path) -> Structure:
    """Read a Pyomo .dat file into a validated Structure (InputError on anything wrong)."""
    path = os.fspath(path)
    text = read_text(path, "Pyomo .dat instance")
    _scan_duplicates(path, text)
    _scan_row_widths(path, text)
    plain = _plain_data(text)
    if plain is not None and set(plain) <= _KNOWN:
        return _structure_from_data(path, plain)
    return _structure_from_data(path, _pyomo_data(path, text))


def _pyomo_data(path, text):
    """The file read by Pyomo's own .dat parser into a DataPortal of :func:`_schema`."""
    from pyomo.environ import DataPortal
    data = DataPortal(model=_schema())
    from pyomo.dataportal import parse_datacmds
    if getattr(parse_datacmds, "dat_lexer", None) is not None:
        parse_datacmds.dat_lexer.lineno = 1  # Pyomo keeps counting lines from the previous file
    try:
        with _plain_copy(path, text) as plain:
            data.load(filename=plain, using="dat")  # by content, whatever the case of the extension
    except Exception as exc:  # Pyomo's parser raises many kinds; all mean a malformed file
        msg = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
        unknown = re.search(r"has no attribute '([^']+)'", msg)
        if unknown:  # data for a component the model does not declare
            raise InputError(_unknown_name(path, text, unknown.group(1))) from None
        raise InputError(f"{path}: not a valid Pyomo .dat instance: {msg}; expected Pyomo data statements "
                         "('set NAME := ... ;', 'param: NAMES := ... ;')") from None
    return data


_KNOWN = {"BLOCKS", "SUPPORTS", "CONTACTS", "vx", "vy", *BLOCK_PARAMS, *BLOCK_MOMENT_PARAMS, *CONTACT_PARAMS,
          *STRENGTH_PARAMS}


def _structure_from_data(path, data) -> Structure:
    """Sets and parameters (a dict or a DataPortal) into a validated Structure."""
    name = os.path.splitext(os.path.basename(path))[0]

    def get_set(key, required=True):
        try:
            members = data[key]
        except (KeyError, ValueError):
            if required:
                raise InputError(f"{path}: set {key} is missing; expected 'set {key} := ... ;'") from None
            return []
        return [str(x) for x in (members or [])]

    def get_param(key):
        try:
            return data[key]
        except (KeyError, ValueError):
            return {}

    blocks, supports, contacts = get_set("BLOCKS"), get_set("SUPPORTS", required=False), get_set("CONTACTS")
    if not blocks:
        raise InputError(f"{path}: the set BLOCKS is empty; expected at least one movable block")

    def column(key, ids, kind, numeric=True, default=None):
        table = get_param(key)
        out = []
        for i in ids:
            if i not in table and default is not None:
                out.append(default)
                continue
            if i not in table:
                raise InputError(f"{path}: parameter {key} of {kind} '{i}' is missing; expected a value for every {kind}")
            v = table[i]
            if numeric:
                try:
                    v = float(v)
                except (TypeError, ValueError):
                    raise InputError(f"{path}: parameter {key} of {kind} '{i}' is '{v}'; expected a number") from None
                if not math.isfinite(v):
                    raise InputError(f"{path}: parameter {key} of {kind} '{i}' is {v}; expected a finite number")
            out.append(v)
        extra = set(map(str, table)) - set(ids)
        if extra:
            raise InputError(f"{path}: parameter {key} is given for '{sorted(extra)[0]}', which is not in the set of "
                             f"{kind}s; expected rows only for the ids of set {kind.upper()}S")
        return out

    bcols = {k: column(k, blocks, "block") for k in BLOCK_PARAMS}
    bcols.update({k: column(k, blocks, "block", default=0.0) for k in BLOCK_MOMENT_PARAMS})
    ccols = {k: column(k, contacts, "contact", numeric=k not in ("block_a", "block_b")) for k in CONTACT_PARAMS}
    strengths = {k: column(k, contacts, "contact", default=JOINT_DEFAULTS[k]) for k in STRENGTH_PARAMS}
    polygons = defaultdict(list)
    vx, vy = get_param("vx"), get_param("vy")
    for key in sorted(vx, key=lambda t: (str(t[0]), int(t[1]))):
        corner = (vx[key], vy.get(key, math.nan))
        try:
            corner = tuple(float(v) for v in corner)
        except (TypeError, ValueError):
            corner = (math.nan, math.nan)
        if not all(math.isfinite(v) for v in corner):
            raise InputError(f"{path}: vertex {key[1]} of '{key[0]}' is ({corner[0]}, {corner[1]}); "
                             "expected finite numbers vx and vy")
        polygons[str(key[0])].append(corner)
    unknown = sorted(set(polygons) - set(blocks) - set(supports))
    if unknown:
        raise InputError(f"{path}: VERTICES lists '{unknown[0]}', which is not in the set of blocks or supports; "
                         "expected vertices only for the ids of sets BLOCKS and SUPPORTS")
    structure = Structure(
        name=name, blocks=blocks,
        centroid=np.column_stack([bcols["x"], bcols["y"]]),
        dead=np.column_stack([bcols["dead_x"], bcols["dead_y"]]),
        live=np.column_stack([bcols["live_x"], bcols["live_y"]]),
        dead_m=bcols["dead_m"], live_m=bcols["live_m"],
        supports=supports, contacts=contacts,
        block_a=[str(v) for v in ccols["block_a"]], block_b=[str(v) for v in ccols["block_b"]],
        centre=np.column_stack([ccols["cx"], ccols["cy"]]).reshape(-1, 2),
        normal=np.column_stack([ccols["nx"], ccols["ny"]]).reshape(-1, 2),
        d=ccols["d"], mu=ccols["mu"], polygons=dict(polygons), **strengths)
    try:
        return structure.validate()
    except InputError as exc:
        raise InputError(f"{path}: {str(exc).split(': ', 1)[1]}") from None
