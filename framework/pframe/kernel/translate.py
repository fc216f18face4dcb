"""Python laws to C: the built-in laws' ``force`` translated into the C kernel, and its header.

A law's ``force`` (``pframe.laws``) is its one definition. It is written in a small subset of
Python — float arithmetic, ``if/elif/else``, local names, ``math.sqrt/exp/log/...``, ``**``,
``abs``, ``min``/``max`` of two values, ``for NAME in range(N)`` with ``break``, reading
``params[i]`` and ``committed[i]``, writing ``trial[i] = ...`` and returning a 3-tuple — which
this module translates to C, statement by statement, in the same order of operations (so the
C kernel computes the same bits as the Python function; a test compares them). Anything else
is refused with the law, line and construct named. The bounded loop is for a law's local
Newton solve (the Bouc-Wen material's, for one).

``python -m pframe.kernel.translate`` writes the two generated files of the C kernel:

- ``c/laws.c``: each built-in law's force as a static C function, and the switches
  ``material_force`` and ``contact_force`` over the law ids of the one ordered registry
  (:func:`pframe.laws.registry.builtin_laws`); ids after the built-in ones call plug-in laws
  through the function pointers in the kernel's Settings;
- ``c/state.h``: the structs and slot names of :mod:`pframe.kernel.state`.

``--check`` exits 1 when either file is stale (the tests run it).
"""

from __future__ import annotations

import ast
import inspect
import math
import sys
import textwrap
from pathlib import Path

from pframe.errors import PframeError

C_FOLDER = Path(__file__).resolve().parent / "c"

#: math functions (``math.NAME``) and their C99 <math.h> names
MATH = {"sqrt": "sqrt", "exp": "exp", "log": "log", "log10": "log10", "sin": "sin",
        "cos": "cos", "tan": "tan", "atan": "atan", "atan2": "atan2", "asin": "asin",
        "acos": "acos", "sinh": "sinh", "cosh": "cosh", "tanh": "tanh", "fabs": "fabs",
        "floor": "floor", "ceil": "ceil", "copysign": "copysign", "pow": "pow",
        "expm1": "expm1", "log1p": "log1p", "hypot": "hypot"}
MATH_CONSTANTS = {"pi": math.pi, "e": math.e, "tau": math.tau}
_BINARY = {ast.Add: "+", ast.Sub: "-", ast.Mult: "*", ast.Div: "/"}
_COMPARE = {ast.Lt: "<", ast.LtE: "<=", ast.Gt: ">", ast.GtE: ">=", ast.Eq: "==",
            ast.NotEq: "!="}
_ARRAYS = ("params", "committed", "trial")


class TranslationError(PframeError):
    """A law's force uses Python that has no C translation here."""


def _number(value) -> str:
    """A C double literal of ``value`` that reads back to the same bits."""
    text = repr(float(value))
    if text in ("inf", "-inf", "nan"):
        return {"inf": "HUGE_VAL", "-inf": "(-HUGE_VAL)", "nan": "NAN"}[text]
    if "e" not in text and "." not in text:
        text += ".0"
    return text


class _Function:
    """The translation of one force function."""

    def __init__(self, function, c_name: str, where: str):
        self.where = where
        try:
            source = textwrap.dedent(inspect.getsource(function))
            _, self.first_line = inspect.getsourcelines(function)
        except (OSError, TypeError) as exc:
            raise TranslationError(f"{where}: the source of force() cannot be read ({exc})") from None
        tree = ast.parse(source)
        node = tree.body[0]
        if not isinstance(node, ast.FunctionDef):
            raise TranslationError(f"{where}: force must be a def (not a lambda)")
        names = [a.arg for a in node.args.args]
        if len(names) != 5 or node.args.vararg or node.args.kwarg or node.args.kwonlyargs:
            raise TranslationError(f"{where}: force takes exactly (params, committed, trial, "
                                   "deformation, rate)")
        # the three arrays and the two scalars, under the law's own names
        self.arrays = dict(zip(names[:3], _ARRAYS))
        self.scalars = {names[3]: "deformation", names[4]: "rate"}
        self.locals: dict[str, str] = {}
        self.counters: list[str] = []  # the C int counters of the loops
        self.hidden: set[str] = set()  # the loops' Python counters: never read
        self.loops = 0
        self.c_name = c_name
        body = node.body
        if body and isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant):
            body = body[1:]  # the docstring
        self.lines = self._block(body, 1)
        if not self._returns(body):
            raise self._error(node, "force must end in a return of (force, d force / d "
                                    "deformation, d force / d rate) on every path")

    def _error(self, node, what: str) -> TranslationError:
        line = self.first_line + getattr(node, "lineno", 1) - 1
        return TranslationError(f"{self.where}, line {line}: {what}. A built-in law's force "
                                "may use float arithmetic, if/elif/else, for NAME in "
                                "range(N) with break, local names, math functions, "
                                "abs/min/max, params[i], committed[i], trial[i] = ... and "
                                "return a 3-tuple (docs/architecture.md)")

    def _returns(self, body) -> bool:
        """Whether every path through ``body`` ends in a return (a loop never counts as one)."""
        if not body:
            return False
        last = body[-1]
        if isinstance(last, ast.Return):
            return True
        if isinstance(last, ast.If):
            return self._returns(last.body) and self._returns(last.orelse)
        return False

    # --- statements -------------------------------------------------------------------------
    def _block(self, body, depth: int) -> list[str]:
        out = []
        for node in body:
            out += self._statement(node, depth)
        return out

    def _statement(self, node, depth: int) -> list[str]:
        pad = "    " * depth
        if isinstance(node, ast.Assign):
            if len(node.targets) != 1:
                raise self._error(node, "one target per assignment")
            return [pad + self._assign(node.targets[0], self._expr(node.value), node) + ";"]
        if isinstance(node, ast.AugAssign):
            op = _BINARY.get(type(node.op))
            if op is None:
                raise self._error(node, f"operator {type(node.op).__name__} in an assignment")
            target = self._target(node.target, node, new=False)
            return [f"{pad}{target} = {target} {op} ({self._expr(node.value)});"]
        if isinstance(node, ast.Return):
            value = node.value
            if not (isinstance(value, ast.Tuple) and len(value.elts) == 3):
                raise self._error(node, "return a tuple of three values")
            parts = [self._expr(v) for v in value.elts]
            return [f"{pad}out[0] = {parts[0]};", f"{pad}out[1] = {parts[1]};",
                    f"{pad}out[2] = {parts[2]};", f"{pad}return;"]
        if isinstance(node, ast.If):
            out = [f"{pad}if ({self._expr(node.test)}) {{"] + self._block(node.body, depth + 1)
            orelse = node.orelse
            while len(orelse) == 1 and isinstance(orelse[0], ast.If):  # elif
                node = orelse[0]
                out += [f"{pad}}} else if ({self._expr(node.test)}) {{"]
                out += self._block(node.body, depth + 1)
                orelse = node.orelse
            if orelse:
                out += [f"{pad}}} else {{"] + self._block(orelse, depth + 1)
            return out + [pad + "}"]
        if isinstance(node, ast.For):
            return self._for(node, depth)
        if isinstance(node, ast.Break):
            if not self.loops:
                raise self._error(node, "break outside a loop")
            return [pad + "break;"]
        if isinstance(node, ast.Pass):
            return []
        if isinstance(node, ast.Expr) and isinstance(node.value, ast.Constant):
            return []  # a string as a comment
        raise self._error(node, f"{type(node).__name__} statements are not translated")

    def _for(self, node, depth: int) -> list[str]:
        """``for NAME in range(N):`` with N a positive integer constant: a bounded loop (a
        law's local Newton solve, say). The counter is the loop's own (an int, read nowhere
        else: the law keeps its own float count if it needs one); ``break`` leaves it."""
        pad = "    " * depth
        call = node.iter
        if not (isinstance(node.target, ast.Name) and isinstance(call, ast.Call)
                and isinstance(call.func, ast.Name) and call.func.id == "range"
                and len(call.args) == 1 and not call.keywords
                and isinstance(call.args[0], ast.Constant) and type(call.args[0].value) is int
                and call.args[0].value > 0) or node.orelse:
            raise self._error(node, "a loop must be `for NAME in range(N):` with N a positive "
                                    "integer constant (and no else)")
        name = node.target.id
        if name in self.arrays or name in self.scalars or name in self.locals:
            raise self._error(node, f"the loop counter {name!r} is already a name of the law")
        counter = f"loop{len(self.counters)}_"
        self.counters.append(counter)
        self.hidden.add(name)
        self.loops += 1
        body = self._block(node.body, depth + 1)
        self.loops -= 1
        return [f"{pad}for ({counter} = 0; {counter} < {call.args[0].value}; {counter}++) {{"] \
            + body + [pad + "}"]

    def _assign(self, target, value: str, node) -> str:
        return f"{self._target(target, node, new=True)} = {value}"

    def _target(self, target, node, new: bool) -> str:
        if isinstance(target, ast.Name):
            name = target.id
            if name in self.arrays or name in self.scalars:
                raise self._error(node, f"the argument {name!r} is assigned to")
            if name in self.hidden:
                raise self._error(node, f"the loop counter {name!r} is assigned to")
            if name not in self.locals:
                if not new:
                    raise self._error(node, f"{name!r} is used before it is assigned")
                self.locals[name] = name + "_"
            return self.locals[name]
        if isinstance(target, ast.Subscript) and isinstance(target.value, ast.Name):
            array = self.arrays.get(target.value.id)
            if array != "trial":
                raise self._error(node, "only trial[i] may be written")
            return f"trial[{self._index(target.slice, node)}]"
        raise self._error(node, "assign to a local name or to trial[i]")

    # --- expressions ------------------------------------------------------------------------
    def _index(self, node, parent) -> str:
        if isinstance(node, ast.Constant) and type(node.value) is int and node.value >= 0:
            return str(node.value)
        raise self._error(parent, "an array index must be a non-negative integer constant")

    def _expr(self, node) -> str:
        if isinstance(node, ast.Constant):
            if isinstance(node.value, bool):
                return "1" if node.value else "0"
            if isinstance(node.value, (int, float)):
                return _number(node.value)
            raise self._error(node, f"the constant {node.value!r} is not a number")
        if isinstance(node, ast.Name):
            if node.id in self.scalars:
                return self.scalars[node.id]
            if node.id in self.locals:
                return self.locals[node.id]
            if node.id in self.hidden:
                raise self._error(node, f"the loop counter {node.id!r} is read (keep a float "
                                        "count of your own)")
            if node.id in ("True", "False"):
                return "1" if node.id == "True" else "0"
            raise self._error(node, f"the name {node.id!r} is not an argument or a local "
                                    "assigned before")
        if isinstance(node, ast.Subscript) and isinstance(node.value, ast.Name):
            if node.value.id not in self.arrays:
                raise self._error(node, f"{node.value.id!r} is not params, committed or trial")
            return f"{self.arrays[node.value.id]}[{self._index(node.slice, node)}]"
        if isinstance(node, ast.BinOp):
            left, right = self._expr(node.left), self._expr(node.right)
            if isinstance(node.op, ast.Pow):
                if isinstance(node.right, ast.Constant) and node.right.value == 2:
                    return f"({left} * {left})"
                return f"pow({left}, {right})"
            op = _BINARY.get(type(node.op))
            if op is None:
                raise self._error(node, f"the operator {type(node.op).__name__}")
            return f"({left} {op} {right})"
        if isinstance(node, ast.UnaryOp):
            operand = self._expr(node.operand)
            if isinstance(node.op, ast.USub):
                return f"(-{operand})"
            if isinstance(node.op, ast.UAdd):
                return operand
            if isinstance(node.op, ast.Not):
                return f"(!{operand})"
            raise self._error(node, f"the operator {type(node.op).__name__}")
        if isinstance(node, ast.Compare):
            parts = []
            left = node.left
            for op, right in zip(node.ops, node.comparators):
                symbol = _COMPARE.get(type(op))
                if symbol is None:
                    raise self._error(node, f"the comparison {type(op).__name__}")
                parts.append(f"({self._expr(left)} {symbol} {self._expr(right)})")
                left = right
            return parts[0] if len(parts) == 1 else "(" + " && ".join(parts) + ")"
        if isinstance(node, ast.BoolOp):
            op = " && " if isinstance(node.op, ast.And) else " || "
            return "(" + op.join(self._expr(v) for v in node.values) + ")"
        if isinstance(node, ast.IfExp):
            return (f"({self._expr(node.test)} ? {self._expr(node.body)} : "
                    f"{self._expr(node.orelse)})")
        if isinstance(node, ast.Attribute):
            if isinstance(node.value, ast.Name) and node.value.id == "math" \
                    and node.attr in MATH_CONSTANTS:
                return _number(MATH_CONSTANTS[node.attr])
            raise self._error(node, f"the attribute {ast.unparse(node)}")
        if isinstance(node, ast.Call):
            return self._call(node)
        raise self._error(node, f"the expression {ast.unparse(node)!r}")

    def _call(self, node) -> str:
        if node.keywords:
            raise self._error(node, "keyword arguments")
        args = [self._expr(a) for a in node.args]
        func = node.func
        if isinstance(func, ast.Attribute) and isinstance(func.value, ast.Name) \
                and func.value.id == "math" and func.attr in MATH:
            return f"{MATH[func.attr]}({', '.join(args)})"
        if isinstance(func, ast.Name):
            if func.id == "abs" and len(args) == 1:
                return f"fabs({args[0]})"
            if func.id in ("min", "max") and len(args) == 2:
                return f"py_{func.id}({args[0]}, {args[1]})"
            if func.id == "float" and len(args) == 1:
                return f"((double)({args[0]}))"
        raise self._error(node, f"the call {ast.unparse(node)!r}")

    def c_source(self) -> str:
        declared = "".join(f"    double {c};\n" for c in self.locals.values())
        declared += "".join(f"    int64_t {c};\n" for c in self.counters)
        declared += ("    (void)params; (void)committed; (void)trial; (void)deformation; "
                     "(void)rate;\n")
        body = "\n".join(self.lines)
        return (f"static void {self.c_name}(const double *params, const double *committed, "
                f"double *trial,\n{' ' * (13 + len(self.c_name))}double deformation, "
                f"double rate, double *out)\n{{\n{declared}{body}\n}}\n")


def translate(law, c_name: str) -> str:
    """The C function ``c_name`` computing ``law.force`` (raises TranslationError)."""
    where = f"{law.kind} law {law.name!r} ({law.__module__}.{law.__qualname__})"
    return _Function(law.force, c_name, where).c_source()


def _law_functions(laws) -> tuple[list[str], dict]:
    """C functions of the laws' force functions (one per distinct Python function: laws that
    share a force share its C) and law -> C name."""
    done: dict[object, str] = {}
    sources, names = [], {}
    for law in laws:
        function = law.force
        if function not in done:
            python_name = function.__name__ if function.__name__ != "force" else law.name
            done[function] = f"{law.kind}_{python_name}"
            sources.append(f"/* {law.__module__}.{law.__qualname__}.force */\n"
                           + translate(law, done[function]))
        names[law] = done[function]
    return sources, names


def laws_c() -> str:
    """The text of c/laws.c."""
    from pframe.laws.registry import builtin_laws

    lines = ["/* Generated by `python -m pframe.kernel.translate` from the built-in laws' Python",
             " * force functions (pframe/laws): do not edit; edit the law and regenerate. */", "",
             '#include "kernel.h"', ""]
    for kind, function, deformation in (("material", "material_force", "drift"),
                                        ("contact", "contact_force", "penetration")):
        laws = builtin_laws(kind)
        sources, names = _law_functions(laws)
        lines += sources
        macro = "BUILTIN_MATERIALS" if kind == "material" else "BUILTIN_CONTACT_LAWS"
        lines += [f"#define {macro} {len(laws)}", "",
                  f"/* (force, d force / d {deformation}, d force / d rate) of {kind} law `law`"
                  f" into out: ids in registry order, then the plug-ins; inlined where the"
                  " element loops call it, so that a law's result stays in registers */",
                  f"static PFRAME_INLINE void {function}(const Settings *s, int64_t law,",
                  "                                      const double *params, "
                  "const double *committed,",
                  f"                                      double *trial, double {deformation}, "
                  "double rate, double *out)",
                  "{", "    switch (law) {"]
        for law_id, law in enumerate(laws):
            lines += [f"    case {law_id}: /* {law.name} */",
                      f"        {names[law]}(params, committed, trial, {deformation}, rate, out);",
                      "        return;"]
        lines += ["    default:",
                  f"        s->{kind}_plugins[law - {macro}](params, committed, trial, "
                  f"{deformation}, rate, out);",
                  "    }", "}", ""]
    return "\n".join(lines)


def _c_field(ctype: str, name: str) -> str:
    if "[" in ctype:  # "double *[N]" or "int64_t[N]"
        base, size = ctype.split("[", 1)
        return f"    {base.strip()}{' ' if not base.endswith('*') else ''}{name}[{size};"
    return f"    {ctype}{'' if ctype.endswith('*') else ' '}{name};"


def state_h() -> str:
    """The text of c/state.h."""
    from pframe.kernel import state

    lines = ["/* Generated by `python -m pframe.kernel.translate` from pframe/kernel/state.py:",
             " * do not edit; edit state.py and regenerate. */", "",
             "#ifndef PFRAME_STATE_H", "#define PFRAME_STATE_H", "", "#include <stdint.h>", "",
             "/* a plug-in law's force (a numba cfunc): params, committed, trial, deformation,",
             " * rate, out[3] = (force, d force / d deformation, d force / d rate) */",
             "typedef void (*LawFunction)(const double *, const double *, double *, double, "
             "double, double *);", ""]
    for title, kind, prefix, count in state.C_CONSTANTS:
        lines.append(f"/* {title} */")
        lines += [f"#define {prefix}{slot.name} {int(slot)}" for slot in kind]
        if count:
            lines.append(f"#define {count} {len(kind)}")
        lines.append("")
    groups = {"Model": state.Model._fields + state.SIZES, "Settings": state.Settings._fields,
              "State": state.State._fields,
              "Recording": state.Recording._fields + state.RECORDING_SIZES,
              "Work": state.Work._fields, "Saved": state.Saved._fields}
    for group, fields in groups.items():
        types = state.C_TYPES[group]
        lines.append(f"typedef struct {group} {{")
        lines += [_c_field(types.get(name, "double *"), name) for name in fields]
        lines += [f"}} {group};", ""]
    lines.append("#endif")
    return "\n".join(lines) + "\n"


def generated() -> dict[Path, str]:
    """The generated files of the C kernel and their current text."""
    return {C_FOLDER / "laws.c": laws_c(), C_FOLDER / "state.h": state_h()}


def stale() -> list[Path]:
    """Generated files that differ from what their sources give now."""
    return [path for path, text in generated().items()
            if not path.exists() or path.read_text(encoding="utf-8") != text]


def main(argv=None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    if argv == ["--check"]:
        old = stale()
        for path in old:
            print(f"{path.name} is stale: run python -m pframe.kernel.translate", file=sys.stderr)
        return 1 if old else 0
    if argv:
        print("usage: python -m pframe.kernel.translate [--check]", file=sys.stderr)
        return 2
    for path, text in generated().items():
        if not path.exists() or path.read_text(encoding="utf-8") != text:
            path.write_text(text, encoding="utf-8", newline="\n")
            print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
