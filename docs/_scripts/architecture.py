"""The package's architecture, read from its code: the import graph by layer, what breaks the rule,
and the picture on the site's architecture page.

The layers are written in ``pyproject.toml`` (``[tool.babyrobot_marl] layers``, bottom row first). The
rule: a module imports only its own subpackage or a lower row; peers on one row never import each
other (the top row, the public face, excepted: ``__init__`` re-exports ``race_v0``). Every import counts, deferred ones and those
under ``TYPE_CHECKING`` too (a circle is a circle to a reader), and a package's ``__init__`` is a module
like any other. Standard library only (``ast``, ``tomllib``, ``graphlib``).

    python docs/_scripts/architecture.py --report     # modules, lines, circles, longest module, problems
    python docs/_scripts/architecture.py --svg out.svg

Module names are relative to the package: ``core.engine``; a package's ``__init__`` is ``core.__init__``,
the root's ``__init__``.
"""

from __future__ import annotations

import ast
import re
import sys
from collections import defaultdict
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
PKG = "babyrobot_marl"
PKG_DIR = ROOT / PKG
MAX_LINES = 500
FACE = "face"  # the top row's name in the picture: the package's public face


def _config(pyproject: Path = ROOT / "pyproject.toml") -> dict:
    text = pyproject.read_text(encoding="utf-8")
    try:
        import tomllib
    except ImportError:  # Python 3.10: the list is a plain literal
        block = text.split("[tool.babyrobot_marl]", 1)[1]
        out = {}
        for key in ("layers",):
            found = re.search(rf"^{key}\s*=\s*(\[.*?\])\s*(#.*)?$", block, re.S | re.M)
            out[key] = ast.literal_eval(re.sub(r"#[^\n]*", "", found.group(1)))
        return out
    return tomllib.loads(text)["tool"]["babyrobot_marl"]


CONFIG = _config()
LAYERS: list[list[str]] = CONFIG["layers"]


def _modules(pkg_dir: Path) -> dict[str, Path]:
    """Module name (relative to the package) -> its file."""
    out = {}
    for path in sorted(pkg_dir.rglob("*.py")):
        out[".".join(path.relative_to(pkg_dir).with_suffix("").parts)] = path
    return out


def _targets(mod: str, node: ast.Import | ast.ImportFrom, mods: dict[str, Path]) -> list[str]:
    """The package modules one import statement reads (none for third-party imports)."""
    parts = mod.split(".")
    package = parts[:-1]  # a module's package; for X.__init__ that is X itself
    if isinstance(node, ast.Import):
        names = [a.name for a in node.names]
        return [t for t in (_module_of(n.split("."), mods, absolute=True) for n in names) if t]
    if node.level:
        base = package[: len(package) - (node.level - 1)]
        dotted = base + (node.module.split(".") if node.module else [])
    else:
        if not node.module or node.module.split(".")[0] != PKG:
            return []
        dotted = node.module.split(".")[1:]
    out = []
    for alias in node.names:
        as_module = ".".join(dotted + [alias.name])
        if as_module in mods:  # from pkg import mod: the module itself
            out.append(as_module)
        elif as_module + ".__init__" in mods:  # from pkg import subpackage: its __init__
            out.append(as_module + ".__init__")
        else:
            target = _module_of(dotted, mods)
            if target:
                out.append(target)
    return out


def _module_of(dotted: list[str], mods: dict[str, Path], absolute: bool = False) -> str | None:
    if absolute:
        if not dotted or dotted[0] != PKG:
            return None
        dotted = dotted[1:]
    name = ".".join(dotted)
    if name in mods:
        return name
    init = ".".join(dotted + ["__init__"])
    return init if init in mods else None


def import_graph(pkg_dir: Path = PKG_DIR) -> dict[str, set[str]]:
    """Every module -> the package modules it imports (anywhere in its file)."""
    mods = _modules(Path(pkg_dir))
    graph: dict[str, set[str]] = {m: set() for m in mods}
    for mod, path in mods.items():
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, (ast.Import, ast.ImportFrom)):
                graph[mod].update(t for t in _targets(mod, node, mods) if t != mod)
    return graph


def layer_of(module: str) -> str:
    """The layer a module belongs to: its subpackage, or a face module's own name."""
    head = module.split(".")[0]
    if module.count(".") == 0 and module not in {m for row in LAYERS for m in row}:
        return module  # an unknown root module: problems() names it
    return head


def _row(layer: str) -> int | None:
    for i, row in enumerate(LAYERS):
        if layer in row:
            return i
    return None


def circles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected components of more than one module (Tarjan), each sorted."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on: set[str] = set()
    out: list[list[str]] = []
    counter = [0]

    def visit(v: str) -> None:
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in sorted(graph.get(v, ())):
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

    sys.setrecursionlimit(max(10_000, sys.getrecursionlimit()))
    for v in sorted(graph):
        if v not in index:
            visit(v)
    return sorted(out)


def line_counts(pkg_dir: Path = PKG_DIR) -> dict[str, int]:
    return {m: len(p.read_text(encoding="utf-8").splitlines()) for m, p in _modules(Path(pkg_dir)).items()}


def check_definers(pkg_dir: Path = PKG_DIR) -> dict[str, list[str]]:
    """Module -> the module-level ``check_*`` / ``_check_*`` functions it defines (an argument rule;
    a method that checks its own object's state, such as ``RaceEnv._check_started``, is not one)."""
    out = {}
    for mod, path in _modules(Path(pkg_dir)).items():
        names = [
            n.name
            for n in ast.parse(path.read_text(encoding="utf-8")).body
            if isinstance(n, (ast.FunctionDef, ast.AsyncFunctionDef)) and n.name.lstrip("_").startswith("check_")
        ]
        if names:
            out[mod] = names
    return out


def problems(graph: dict[str, set[str]], pkg_dir: Path = PKG_DIR) -> list[str]:
    """Every break of the rules, one line each: circles, upward or peer edges,
    modules over MAX_LINES lines, check_* defined outside a checks.py, unknown root modules."""
    out = [f"circle: {' <-> '.join(c)}" for c in circles(graph)]
    for mod in sorted(graph):
        src = layer_of(mod)
        if _row(src) is None:
            out.append(f"unknown layer: {mod} (add it to [tool.babyrobot_marl] layers)")
        for dep in sorted(graph[mod]):
            dst = layer_of(dep)
            if src == dst:
                continue
            a, b = _row(src), _row(dst)
            if a is None or b is None:
                continue
            if b > a:
                out.append(f"upward: {mod} ({src}) -> {dep} ({dst})")
            elif b == a and a != len(LAYERS) - 1:  # the face's modules may re-export each other
                out.append(f"peer: {mod} ({src}) -> {dep} ({dst})")
    for mod, n in sorted(line_counts(pkg_dir).items()):
        if n > MAX_LINES:
            out.append(f"long: {mod} has {n} lines (most {MAX_LINES})")
    for mod, names in sorted(check_definers(pkg_dir).items()):
        if mod.split(".")[-1] != "checks":
            out.append(f"check outside checks.py: {mod} defines {', '.join(names)}")
    return out


def _boxes(graph: dict[str, set[str]]) -> dict[str, list[str]]:
    """Box (subpackage, or a face module) -> its modules."""
    boxes: dict[str, list[str]] = defaultdict(list)
    for mod in graph:
        boxes[layer_of(mod)].append(mod)
    return boxes


def svg(graph: dict[str, set[str]], pkg_dir: Path = PKG_DIR) -> str:
    """The import graph by layer: one row per layer (bottom row at the bottom), one box per
    subpackage with its module and line counts, and one arrow per pair of boxes that import each
    other, labelled with the number of module-to-module imports. Fixed coordinates: the same code
    gives the same picture."""
    lines = line_counts(pkg_dir)
    boxes = _boxes(graph)
    box_w, box_h, gap_x, gap_y, pad = 150, 46, 40, 60, 20
    widest = max(len(row) for row in LAYERS)
    width = pad * 2 + widest * box_w + (widest - 1) * gap_x + 90
    height = pad * 2 + len(LAYERS) * box_h + (len(LAYERS) - 1) * gap_y
    pos: dict[str, tuple[float, float]] = {}
    parts = []
    for i, row in enumerate(LAYERS):
        y = height - pad - (i + 1) * box_h - i * gap_y
        row_w = len(row) * box_w + (len(row) - 1) * gap_x
        x0 = 90 + pad + (width - 90 - 2 * pad - row_w) / 2
        label = FACE if row == LAYERS[-1] else f"layer {i}"
        parts.append(f'<text x="{pad}" y="{y + box_h / 2 + 4:.0f}" class="row">{label}</text>')
        for j, name in enumerate(row):
            x = x0 + j * (box_w + gap_x)
            pos[name] = (x, y)
            mods = boxes.get(name, [])
            n_lines = sum(lines.get(m, 0) for m in mods)
            title = name if row != LAYERS[-1] else f"{name}.py"
            parts.append(f'<rect x="{x:.0f}" y="{y:.0f}" width="{box_w}" height="{box_h}" rx="6" class="box"/>')
            parts.append(f'<text x="{x + box_w / 2:.0f}" y="{y + 19:.0f}" class="name">{title}</text>')
            parts.append(
                f'<text x="{x + box_w / 2:.0f}" y="{y + 36:.0f}" class="size">{len(mods)} module{"s" * (len(mods) != 1)}, '
                f"{n_lines:,} lines</text>"
            )
    counts: dict[tuple[str, str], int] = defaultdict(int)
    for mod, deps in graph.items():
        for dep in deps:
            a, b = layer_of(mod), layer_of(dep)
            if a != b and a in pos and b in pos:
                counts[(a, b)] += 1
    arrows = []
    for (a, b), n in sorted(counts.items()):
        (xa, ya), (xb, yb) = pos[a], pos[b]
        x1, y1 = xa + box_w / 2, ya + (box_h if yb > ya else 0)
        x2, y2 = xb + box_w / 2, yb + (0 if yb > ya else box_h)
        if ya == yb:  # a peer edge (a break of the rule): drawn along the row
            y1 = y2 = ya + box_h / 2
            x1, x2 = (xa + box_w, xb) if xb > xa else (xa, xb + box_w)
        arrows.append(f'<line x1="{x1:.0f}" y1="{y1:.0f}" x2="{x2:.0f}" y2="{y2:.0f}" class="edge"/>')
        arrows.append(f'<text x="{(x1 + 2 * x2) / 3 + 4:.0f}" y="{(y1 + 2 * y2) / 3:.0f}" class="count">{n}</text>')
    style = (
        "<style>.box{fill:#f4f1ea;stroke:#5a4a3a;stroke-width:1.5}.name{font:bold 14px sans-serif;text-anchor:middle}"
        ".size{font:11px sans-serif;text-anchor:middle;fill:#555}.row{font:12px sans-serif;fill:#777}"
        ".edge{stroke:#8a7a6a;stroke-width:1;marker-end:url(#arrow);opacity:.7}.count{font:10px sans-serif;fill:#8a3a2a}</style>"
    )
    marker = (
        '<defs><marker id="arrow" viewBox="0 0 10 10" refX="10" refY="5" markerWidth="6" markerHeight="6" orient="auto">'
        '<path d="M0,0 L10,5 L0,10 z" fill="#8a7a6a"/></marker></defs>'
    )
    return (
        f'<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" viewBox="0 0 {width} {height}">'
        f"<title>babyrobot_marl: imports by layer (arrows point to the imported layer)</title>{style}{marker}"
        + "".join(arrows + parts)
        + "</svg>\n"
    )


def report(pkg_dir: Path = PKG_DIR) -> str:
    graph = import_graph(pkg_dir)
    lines = line_counts(pkg_dir)
    longest = max(lines, key=lambda m: lines[m])
    found = problems(graph, pkg_dir)
    checks = list(check_definers(pkg_dir))
    head = (
        f"arch: {len(lines)} modules, {sum(lines.values()):,} lines; circles {len(circles(graph))}; "
        f"longest {longest} {lines[longest]}; check modules {len(checks)}; problems {len(found)}"
    )
    return "\n".join([*found, head])


if __name__ == "__main__":
    args = sys.argv[1:]
    if args == ["--report"]:
        print(report())
    elif len(args) == 2 and args[0] == "--svg":
        Path(args[1]).write_text(svg(import_graph()), encoding="utf-8")
    else:
        sys.exit("usage: python docs/_scripts/architecture.py --report | --svg OUT.svg")
