"""No C file of the FMUs calls into a file that calls it back (directly or around a longer loop).

The C sources under fmu_src/ are parsed here (comments and literals removed, brace depth tracked):
a function definition is a name followed by a parameter list and a body at file level, a call is a
name followed by "(" inside a body. File A calls file B when a body in A calls a function that B
defines without `static`. Calls through function pointers (the layer reaching a model through
FmiModel) are not edges, which is the point: the layer and the models meet only through the table.
"""

from __future__ import annotations

import re
from pathlib import Path

FMU_SRC = Path(__file__).resolve().parents[2] / "fmu_src"
KEYWORDS = {"if", "for", "while", "switch", "return", "sizeof", "do", "else", "case"}


def _strip(text: str) -> str:
    """The C text without comments, string and character literals or preprocessor lines."""
    text = re.sub(r"/\*.*?\*/", " ", text, flags=re.S)
    text = re.sub(r"//[^\n]*", " ", text)
    text = re.sub(r'"(?:\\.|[^"\\])*"', '""', text)
    text = re.sub(r"'(?:\\.|[^'\\])*'", "''", text)
    return re.sub(r"^\s*#[^\n]*(?:\\\n[^\n]*)*", " ", text, flags=re.M)


def parse(text: str) -> tuple[dict[str, bool], set[str]]:
    """(function name -> defined static, names called in the bodies) of one C file."""
    code = _strip(text)
    defs: dict[str, bool] = {}
    calls: set[str] = set()
    depth, body_start, i = 0, 0, 0
    for m in re.finditer(r"[{}]", code):
        if m.group() == "{":
            if depth == 0:
                head = code[i : m.start()]
                sig = re.search(r"(\w+)\s*\(([^()]|\([^()]*\))*\)\s*$", head)
                if sig and "=" not in head:  # not an initializer such as `x = {...}`
                    defs[sig.group(1)] = bool(re.search(r"\bstatic\b", head[: sig.start()].split(";")[-1]))
                body_start = m.end()
            depth += 1
        else:
            depth -= 1
            if depth == 0:
                calls |= {
                    c for c in re.findall(r"\b([A-Za-z_]\w*)\s*\(", code[body_start : m.start()]) if c not in KEYWORDS
                }
                i = m.end()
    return defs, calls


def call_graph() -> dict[str, set[str]]:
    """File (relative to fmu_src/) -> the files whose non-static functions it calls."""
    parsed = {p.relative_to(FMU_SRC).as_posix(): parse(p.read_text()) for p in sorted(FMU_SRC.rglob("*.c"))}
    owner: dict[str, str] = {}
    for f, (defs, _) in parsed.items():
        for name, is_static in defs.items():
            if not is_static:
                owner[name] = f
    graph: dict[str, set[str]] = {}
    for f, (defs, calls) in parsed.items():
        graph[f] = {owner[c] for c in calls if c in owner and owner[c] != f and c not in defs}
    return graph


def cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """Every file loop found by a depth-first search (empty: the calls go one way)."""
    found, state = [], {}

    def visit(f: str, path: list[str]) -> None:
        state[f] = 1
        for g in sorted(graph.get(f, ())):
            if state.get(g) == 1:
                found.append(path[path.index(g) :] + [g])
            elif g not in state:
                visit(g, path + [g])
        state[f] = 2

    for f in sorted(graph):
        if f not in state:
            visit(f, [f])
    return found


def test_parser_sees_definitions_and_calls():
    defs, calls = parse(
        "static int a(int x)\n{\n    return b(x) + sizeof(x);\n}\n"
        "int c(void) { /* d() */ return a(1); }\nconst T t = {f, g};\n"
    )
    assert defs == {"a": True, "c": False} and calls == {"a", "b"}


def test_cycle_search_finds_a_loop():
    assert cycles({"x.c": {"y.c"}, "y.c": {"z.c"}, "z.c": {"x.c"}}) == [["x.c", "y.c", "z.c", "x.c"]]
    assert cycles({"x.c": {"y.c"}, "y.c": set()}) == []


def test_the_build_is_reached_from_both_sides_and_calls_neither():
    # outputs (variables.c) and the end of initialization (instance.c) both build the model's data:
    # through build.c, which calls only the model's function pointers (and fsm.c)
    graph = call_graph()
    assert "fmi/build.c" in graph["fmi/variables.c"] and "fmi/build.c" in graph["fmi/instance.c"]
    assert graph["fmi/build.c"] <= {"fmi/fsm.c"}


def test_no_c_file_calls_into_a_file_that_calls_it_back():
    assert cycles(call_graph()) == []
