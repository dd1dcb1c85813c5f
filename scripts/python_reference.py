#!/usr/bin/env python3
"""The Python API reference (docs/src/reference/python.md), generated from the package's sources.

Reads ``python/decohesion/__init__.py`` (the exported names, the package's docstring) and the
stubs ``python/decohesion/_native.pyi`` (classes, methods, properties, attributes, signatures and
docstrings) with ``ast``, without importing the package (no build needed), and writes Markdown.

    python3 scripts/python_reference.py                 # the page to standard output
    python3 scripts/python_reference.py --out FILE      # the page to FILE
    python3 scripts/python_reference.py --check         # exit 1 if the committed page is stale

Standard library only.
"""

from __future__ import annotations

import argparse
import ast
import inspect
import re
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
PACKAGE = REPO / "python" / "decohesion"
INIT = PACKAGE / "__init__.py"
STUBS = PACKAGE / "_native.pyi"
PAGE = REPO / "docs" / "src" / "reference" / "python.md"
REGENERATE = "python3 scripts/python_reference.py --out docs/src/reference/python.md"


def markdown_text(doc: str) -> str:
    """A reStructuredText-ish docstring as Markdown: ``code`` becomes `code`, and a run of
    doctest lines (``>>>``) a fenced Python block."""
    doc = re.sub(r"``(.+?)``", r"`\1`", doc, flags=re.S)
    out: list[str] = []
    in_code = False
    for line in doc.splitlines():
        is_code = line.startswith(">>>")
        if is_code and not in_code:
            out.append("```python")
        if not is_code and in_code:
            out.append("```")
        in_code = is_code
        out.append(line)
    if in_code:
        out.append("```")
    return "\n".join(out).strip()


def one_line(doc: str) -> str:
    """A docstring as one table cell: whitespace collapsed, ``|`` escaped."""
    return " ".join(markdown_text(doc).split()).replace("|", "\\|")


def docstring(node: ast.AST) -> str:
    """The node's docstring, cleaned (``inspect.cleandoc``); empty if it has none."""
    doc = ast.get_docstring(node, clean=True)  # type: ignore[arg-type]
    return doc or ""


def annotation(node: ast.expr | None) -> str:
    return ast.unparse(node) if node is not None else ""


def signature(fn: ast.FunctionDef, drop_self: bool) -> str:
    """``name(a: int, b: str = "x", *, c=None) -> T`` of a function, without ``self``."""
    args = fn.args
    parts: list[str] = []

    def one(arg: ast.arg, default: ast.expr | None) -> str:
        text = arg.arg
        if arg.annotation is not None:
            text += f": {annotation(arg.annotation)}"
            if default is not None:
                text += f" = {ast.unparse(default)}"
        elif default is not None:
            text += f"={ast.unparse(default)}"
        return text

    positional = args.posonlyargs + args.args
    defaults: list[ast.expr | None] = [None] * (len(positional) - len(args.defaults))
    defaults += list(args.defaults)
    for i, (arg, default) in enumerate(zip(positional, defaults)):
        if i == 0 and drop_self and arg.arg in ("self", "cls"):
            continue
        parts.append(one(arg, default))
        if args.posonlyargs and arg is args.posonlyargs[-1]:
            parts.append("/")
    if args.vararg is not None:
        parts.append("*" + one(args.vararg, None))
    elif args.kwonlyargs:
        parts.append("*")
    for arg, default in zip(args.kwonlyargs, args.kw_defaults):
        parts.append(one(arg, default))
    if args.kwarg is not None:
        parts.append("**" + one(args.kwarg, None))
    returns = f" -> {annotation(fn.returns)}" if fn.returns is not None else ""
    return f"{fn.name}({', '.join(parts)}){returns}"


def decorators(fn: ast.FunctionDef) -> list[str]:
    return [ast.unparse(d) for d in fn.decorator_list]


def comment_above(source_lines: list[str], lineno: int) -> str:
    """The ``#:`` comment lines right above line ``lineno`` (1-based), joined."""
    lines: list[str] = []
    i = lineno - 2
    while i >= 0 and source_lines[i].strip().startswith("#:"):
        lines.insert(0, source_lines[i].strip()[2:].strip())
        i -= 1
    return " ".join(lines)


def attribute_docs(body: list[ast.stmt]) -> list[tuple[str, str, str]]:
    """(name, type, docstring) of annotated attributes, each docstring the string literal that
    follows it (the attribute-docstring convention)."""
    found: list[tuple[str, str, str]] = []
    for i, stmt in enumerate(body):
        if isinstance(stmt, ast.AnnAssign) and isinstance(stmt.target, ast.Name):
            doc = ""
            following = body[i + 1] if i + 1 < len(body) else None
            if (
                isinstance(following, ast.Expr)
                and isinstance(following.value, ast.Constant)
                and isinstance(following.value.value, str)
            ):
                doc = inspect.cleandoc(following.value.value)
            found.append((stmt.target.id, annotation(stmt.annotation), doc))
    return found


def exported_names(init: ast.Module) -> list[str]:
    """``__all__`` of the package."""
    for stmt in init.body:
        if (
            isinstance(stmt, ast.Assign)
            and any(isinstance(t, ast.Name) and t.id == "__all__" for t in stmt.targets)
            and isinstance(stmt.value, (ast.List, ast.Tuple))
        ):
            return [e.value for e in stmt.value.elts if isinstance(e, ast.Constant)]
    return []


def class_section(cls: ast.ClassDef, out: list[str]) -> None:
    bases = ", ".join(ast.unparse(b) for b in cls.bases)
    title = f"{cls.name}({bases})" if bases else cls.name
    out.append(f"## class `{title}`\n")
    doc = docstring(cls)
    if doc:
        out.append(markdown_text(doc) + "\n")
    attributes = attribute_docs(cls.body)
    if attributes:
        out.append("| attribute | type | description |")
        out.append("| --- | --- | --- |")
        for name, kind, adoc in attributes:
            out.append(f"| `{name}` | `{kind}` | {one_line(adoc)} |")
        out.append("")
    functions = [s for s in cls.body if isinstance(s, ast.FunctionDef)]
    properties = [f for f in functions if "property" in decorators(f)]
    methods = [f for f in functions if "property" not in decorators(f)]
    for fn in methods:
        if fn.name.startswith("_") and fn.name != "__init__":
            continue
        kind = ""
        if "staticmethod" in decorators(fn):
            kind = " (static method)"
        elif "classmethod" in decorators(fn):
            kind = " (class method)"
        if fn.name == "__init__":
            shown = signature(fn, drop_self=True).replace(fn.name, cls.name, 1)
            out.append(f"### `{cls.name}(…)` (constructor)\n")
        else:
            shown = signature(fn, drop_self=True).replace(fn.name, f"{cls.name}.{fn.name}", 1)
            out.append(f"### `{cls.name}.{fn.name}`{kind}\n")
        out.append(f"```python\n{shown}\n```\n")
        fdoc = docstring(fn)
        if fdoc:
            out.append(markdown_text(fdoc) + "\n")
    if properties:
        out.append(f"### Properties of `{cls.name}` (read-only)\n")
        out.append("| property | type | description |")
        out.append("| --- | --- | --- |")
        for fn in properties:
            out.append(
                f"| `{fn.name}` | `{annotation(fn.returns)}` | {one_line(docstring(fn))} |"
            )
        out.append("")


def generate() -> str:
    """The page, from the sources as they are now."""
    init_source = INIT.read_text(encoding="utf-8")
    stub_source = STUBS.read_text(encoding="utf-8")
    init = ast.parse(init_source, filename=str(INIT))
    stubs = ast.parse(stub_source, filename=str(STUBS))
    stub_lines = stub_source.splitlines()
    out: list[str] = [
        "<!-- @generated by `python3 scripts/python_reference.py` from "
        "python/decohesion/__init__.py and python/decohesion/_native.pyi: do not edit. -->\n",
        "# Python API\n",
    ]
    out.append(markdown_text(docstring(init)) + "\n")
    names = exported_names(init)
    if names:
        listed = ", ".join(f"`{n}`" for n in names)
        out.append(f"`import decohesion` exports {listed}.\n")
    stub_doc = docstring(stubs)
    if stub_doc:
        out.append(markdown_text(stub_doc) + "\n")
    values: list[str] = []
    for stmt in stubs.body:
        if isinstance(stmt, ast.AnnAssign) and isinstance(stmt.target, ast.Name):
            doc = one_line(comment_above(stub_lines, stmt.lineno))
            values.append(f"| `{stmt.target.id}` | `{annotation(stmt.annotation)}` | {doc} |")
        elif (
            isinstance(stmt, ast.Assign)
            and len(stmt.targets) == 1
            and isinstance(stmt.targets[0], ast.Name)
        ):
            doc = one_line(comment_above(stub_lines, stmt.lineno))
            values.append(f"| `{stmt.targets[0].id}` | `{ast.unparse(stmt.value)}` | {doc} |")
    if values:
        out.append("## Module values and types\n")
        out.append("| name | type | description |")
        out.append("| --- | --- | --- |")
        out.extend(values)
        out.append("")
    for stmt in stubs.body:
        if isinstance(stmt, ast.ClassDef):
            class_section(stmt, out)
        elif isinstance(stmt, ast.FunctionDef) and not stmt.name.startswith("_"):
            out.append(f"## `{stmt.name}`\n")
            out.append(f"```python\n{signature(stmt, drop_self=False)}\n```\n")
            if docstring(stmt):
                out.append(markdown_text(docstring(stmt)) + "\n")
    return "\n".join(out).rstrip("\n") + "\n"


def check(page: Path = PAGE) -> str | None:
    """None if ``page`` is what the sources generate, else what is wrong and how to fix it."""
    fresh = generate()
    committed = page.read_text(encoding="utf-8") if page.exists() else ""
    if committed == fresh:
        return None
    old, new = committed.splitlines(), fresh.splitlines()
    line = next(
        (i for i, (a, b) in enumerate(zip(old, new)) if a != b), min(len(old), len(new))
    )
    shown = lambda lines: lines[line] if line < len(lines) else "(end of file)"  # noqa: E731
    rel = page.relative_to(REPO) if page.is_relative_to(REPO) else page
    return (
        f"{rel} is stale: run `{REGENERATE}` (or scripts/gen_reference.sh)\n"
        f"first difference at line {line + 1}:\n"
        f"  committed: {shown(old)}\n"
        f"  generated: {shown(new)}"
    )


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    group = parser.add_mutually_exclusive_group()
    group.add_argument("--out", type=Path, help="write the page to this file")
    group.add_argument(
        "--check",
        action="store_true",
        help=f"exit 1 if {PAGE.relative_to(REPO)} differs from what the sources generate",
    )
    args = parser.parse_args(argv)
    if args.check:
        problem = check()
        if problem:
            print(problem, file=sys.stderr)
            return 1
        print(f"{PAGE.relative_to(REPO)} is up to date")
        return 0
    text = generate()
    if args.out:
        args.out.parent.mkdir(parents=True, exist_ok=True)
        args.out.write_text(text, encoding="utf-8")
    else:
        sys.stdout.write(text)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
