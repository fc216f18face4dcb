"""Python laws to C: the built-in laws' ``force`` translated into the C kernel, and its header.

A law's ``force`` (``pframe.laws``) is its one definition. It is written in a small subset of
Python — float arithmetic, ``if/elif/else``, local names, ``math.sqrt/exp/log/...``, ``**``,
``abs``, ``min``/``max`` of two values, ``for NAME in range(N)`` with ``break``, reading
``params[i]`` and ``committed[i]``, writing ``trial[i] = ...``, module-level numbers, calls of
module-level helper functions, and returning a 3-tuple — which this module translates to C,
statement by statement, in the same order of operations (so the C kernel computes the same
bits as the Python function; a test compares them). Anything else is refused with the law,
line and construct named. The bounded loop is for a law's local Newton solve (the Bouc-Wen
material's, for one).

A helper function (a plain ``def`` at module level, in the law's module or imported into it)
is written in the same subset and becomes a ``static`` C function, translated once however
many laws call it: so a long law splits into named pieces and two laws share theirs (Bouc-Wen
and BWBN their Newton solve for z). Its arguments are numbers, or the law's arrays passed
whole (``params``, ``committed``, ``trial``: a helper may write ``trial[i]`` when it is given
``trial``); it returns nothing, a number (used in an expression) or a tuple (unpacked,
``a, b = helper(...)``, or returned as the force's three numbers). It may not call itself.

``python -m pframe.kernel.translate`` writes the two generated files of the C kernel:

- ``c/laws.c``: each built-in law's force as a static C function, the lists
  ``MATERIAL_LAWS`` and ``CONTACT_LAWS`` (id, function) from which assembly.c makes each
  law group's loop, and the switches ``material_force`` and ``contact_force`` (one law's
  force, for the laws' tests) over the law ids of the one ordered registry
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


def _parse(function, where: str):
    """The ``def`` of ``function`` (its ast node) and the line it starts on."""
    try:
        source = textwrap.dedent(inspect.getsource(function))
        _, first_line = inspect.getsourcelines(function)
    except (OSError, TypeError) as exc:
        raise TranslationError(f"{where}: the source cannot be read ({exc})") from None
    node = ast.parse(source).body[0]
    if not isinstance(node, ast.FunctionDef):
        raise TranslationError(f"{where}: must be a def (not a lambda)")
    return node, first_line


def _without_docstring(body):
    if body and isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant):
        return body[1:]
    return body


class _Unit:
    """The helper functions of one C file: each module-level Python function a law calls is
    translated once, into a static C function emitted before its first caller."""

    def __init__(self):
        self.helpers: dict[object, _Helper] = {}
        self.pending: list[str] = []  # C of helpers not yet written out
        self.c_names: set[str] = set()
        self.active: list = []  # the helpers being translated (a call among them recurses)
        self.kinds: dict[object, object] = {}  # function -> what it returns (see _Helper)

    def helper(self, function, arrays: tuple, caller) -> _Helper:
        """The translation of ``function`` called with array arguments at positions where
        ``arrays`` is True (the same at every call)."""
        if function in self.active:
            raise caller.fail(f"{function.__qualname__} calls itself (directly or through "
                              "another helper): recursion is not translated")
        done = self.helpers.get(function)
        if done is not None:
            if done.array_args != arrays:
                raise caller.fail(f"{function.__qualname__} is called with arrays in other "
                                  "places than before (each argument is an array at every "
                                  "call, or a number at every call)")
            return done
        tail = function.__module__.rsplit(".", 1)[-1].strip("_")
        c_name, n = f"{tail}_{function.__name__}", 2
        while c_name in self.c_names:
            c_name, n = f"{tail}_{function.__name__}{n}", n + 1
        self.c_names.add(c_name)
        self.active.append(function)
        try:
            helper = _Helper(function, c_name, arrays, self, caller)
        finally:
            self.active.pop()
        self.helpers[function] = helper
        self.pending.append(helper.c_source())
        return helper

    def returns(self, function, caller):
        """What ``function`` returns: "void" (nothing), "scalar" (a number) or the length of
        the tuple it returns, the same on every return."""
        if function in self.kinds:
            if self.kinds[function] is None:
                raise caller.fail(f"{function.__qualname__} calls itself (directly or through "
                                  "another helper): recursion is not translated")
            return self.kinds[function]
        self.kinds[function] = None
        where = f"{function.__module__}.{function.__qualname__}"
        node, first_line = _parse(function, where)
        found = set()
        for item in ast.walk(node):
            if isinstance(item, (ast.FunctionDef, ast.Lambda)) and item is not node:
                raise TranslationError(f"{where}, line {first_line + item.lineno - 1}: a "
                                       "function inside a function is not translated")
            if not isinstance(item, ast.Return):
                continue
            value = item.value
            if value is None:
                found.add("void")
            elif isinstance(value, ast.Tuple):
                found.add(len(value.elts))
            elif isinstance(value, ast.Call) and caller.helper_function(value.func):
                found.add(self.returns(caller.helper_function(value.func), caller))
            else:
                found.add("scalar")
        if len(found) > 1:
            raise TranslationError(f"{where}: returns {' and '.join(sorted(map(str, found)))} "
                                   "on different paths (a helper returns nothing, a number or "
                                   "a tuple of one length on every path)")
        self.kinds[function] = found.pop() if found else "void"
        return self.kinds[function]

    def take(self) -> list[str]:
        """The C of the helpers translated since the last call."""
        out, self.pending = self.pending, []
        return out


class _Body:
    """The translation of one Python function: a law's force or a helper it calls."""

    def __init__(self, function, where: str, unit: _Unit):
        self.where = where
        self.unit = unit
        self.globals = getattr(function, "__globals__", {})
        node, self.first_line = _parse(function, where)
        self.node = node
        if node.args.vararg or node.args.kwarg or node.args.kwonlyargs or node.args.defaults \
                or node.args.posonlyargs:
            raise self.fail("only plain positional arguments (no defaults, *args or **kwargs)")
        self.arrays: dict[str, str] = {}  # Python name -> C name of an array argument
        self.scalars: dict[str, str] = {}  # read-only number arguments
        self.locals: dict[str, str] = {}
        self.counters: list[str] = []  # the C int counters of the loops
        self.hidden: set[str] = set()  # the loops' Python counters: never read
        self.loops = 0

    def fail(self, what: str, node=None) -> TranslationError:
        line = self.first_line + getattr(node if node is not None else self.node, "lineno", 1) - 1
        return TranslationError(f"{self.where}, line {line}: {what}. A built-in law's force "
                                "may use float arithmetic, if/elif/else, for NAME in "
                                "range(N) with break, local names, math functions, "
                                "abs/min/max, params[i], committed[i], trial[i] = ..., "
                                "module-level numbers and calls of module-level helper "
                                "functions, and return a 3-tuple (docs/architecture.md)")

    def _error(self, node, what: str) -> TranslationError:
        return self.fail(what, node)

    def writable(self, c_array: str, node) -> None:
        """Refuse a write (or a pass to a helper that writes) into a read-only array."""
        raise self._error(node, "only trial[i] may be written")

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

    def helper_function(self, func):
        """The module-level Python function a call's ``func`` names, or None."""
        if isinstance(func, ast.Name) and func.id not in self.locals \
                and func.id not in self.scalars and func.id not in self.arrays:
            value = self.globals.get(func.id)
            if inspect.isfunction(value):
                return value
        return None

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
            target = node.targets[0]
            if isinstance(target, ast.Tuple):
                return [pad + self._unpack(target, node.value, node) + ";"]
            return [pad + self._assign(target, self._expr(node.value), node) + ";"]
        if isinstance(node, ast.AugAssign):
            op = _BINARY.get(type(node.op))
            if op is None:
                raise self._error(node, f"operator {type(node.op).__name__} in an assignment")
            target = self._target(node.target, node, new=False)
            return [f"{pad}{target} = {target} {op} ({self._expr(node.value)});"]
        if isinstance(node, ast.Return):
            return [pad + line for line in self._return(node)]
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
        if isinstance(node, ast.Expr) and isinstance(node.value, ast.Call) \
                and self.helper_function(node.value.func):
            helper, args = self._helper_call(node.value)
            if helper.returns != "void":
                raise self._error(node, f"the result of {helper.qualname} is dropped")
            return [f"{pad}{helper.c_name}({', '.join(args)});"]
        raise self._error(node, f"{type(node).__name__} statements are not translated")

    def _return(self, node) -> list[str]:
        raise NotImplementedError

    def _tuple_call(self, value, arity: int, node) -> tuple:
        """A call of a helper that returns a tuple of ``arity`` numbers: (helper, args)."""
        if not (isinstance(value, ast.Call) and self.helper_function(value.func)):
            return None, None
        helper, args = self._helper_call(value)
        if helper.returns != arity:
            raise self._error(node, f"{helper.qualname} returns {helper.returns}, not a tuple "
                                    f"of {arity} numbers")
        return helper, args

    def _unpack(self, target, value, node) -> str:
        """``a, b = helper(...)``: the helper writes the names through pointers."""
        names = target.elts
        helper, args = self._tuple_call(value, len(names), node)
        if helper is None:
            raise self._error(node, "a tuple is assigned only from a helper function that "
                                    "returns one")
        if not all(isinstance(n, ast.Name) for n in names):
            raise self._error(node, "a helper's tuple is unpacked into local names")
        pointers = ["&" + self._target(n, node, new=True) for n in names]
        return f"{helper.c_name}({', '.join(args + pointers)})"

    def _for(self, node, depth: int) -> list[str]:
        """``for NAME in range(N):`` with N a positive integer constant: a bounded loop (a
        law's local Newton solve, say). The counter is the loop's own (an int, read nowhere
        else: the law keeps its own float count if it needs one); ``break`` leaves it."""
        pad = "    " * depth
        call = node.iter
        bound = None
        if isinstance(call, ast.Call) and len(call.args) == 1:
            bound = call.args[0].value if isinstance(call.args[0], ast.Constant) \
                else self._constant(call.args[0])
        if not (isinstance(node.target, ast.Name) and isinstance(call, ast.Call)
                and isinstance(call.func, ast.Name) and call.func.id == "range"
                and len(call.args) == 1 and not call.keywords
                and type(bound) is int and bound > 0) or node.orelse:
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
        return [f"{pad}for ({counter} = 0; {counter} < {bound}; {counter}++) {{"] \
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
        if isinstance(target, ast.Subscript) and isinstance(target.value, ast.Name) \
                and target.value.id in self.arrays:
            array = self.arrays[target.value.id]
            self.writable(array, node)
            return f"{array}[{self._index(target.slice, node)}]"
        if isinstance(target, ast.Subscript):
            raise self._error(node, "only trial[i] may be written")
        raise self._error(node, "assign to a local name or to trial[i]")

    # --- expressions ------------------------------------------------------------------------
    def _index(self, node, parent) -> str:
        value = node.value if isinstance(node, ast.Constant) else self._constant(node)
        if type(value) is int and value >= 0:
            return str(value)
        raise self._error(parent, "an array index must be a non-negative integer constant "
                                  "(a number or a module-level name of one)")

    def _constant(self, node):
        """The value of a module-level number that ``node`` names, or None."""
        if isinstance(node, ast.Name) and node.id not in self.locals \
                and node.id not in self.scalars and node.id not in self.arrays:
            value = self.globals.get(node.id)
            if type(value) in (int, float):
                return value
        return None

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
            if self._constant(node) is not None:
                return _number(self._constant(node))
            raise self._error(node, f"the name {node.id!r} is not an argument, a local "
                                    "assigned before or a module-level number")
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

    def _helper_call(self, node):
        """A call of a module-level helper: (its translation, the C arguments). An argument
        that is one of the caller's arrays is passed as that array; any other is a number."""
        if node.keywords:
            raise self._error(node, "keyword arguments")
        function = self.helper_function(node.func)
        arrays = tuple(isinstance(a, ast.Name) and a.id in self.arrays for a in node.args)
        args = [self.arrays[a.id] if is_array else self._expr(a)
                for a, is_array in zip(node.args, arrays)]
        helper = self.unit.helper(function, arrays, self)
        if len(args) != helper.arity:
            raise self._error(node, f"{helper.qualname} takes {helper.arity} arguments, "
                                    f"given {len(args)}")
        for arg, written in zip(args, helper.written):
            if written:
                self.writable(arg, node)
        return helper, args

    def _call(self, node) -> str:
        if node.keywords:
            raise self._error(node, "keyword arguments")
        func = node.func
        if isinstance(func, ast.Attribute) and isinstance(func.value, ast.Name) \
                and func.value.id == "math" and func.attr in MATH:
            args = [self._expr(a) for a in node.args]
            return f"{MATH[func.attr]}({', '.join(args)})"
        if isinstance(func, ast.Name) and func.id in ("abs", "min", "max", "float"):
            args = [self._expr(a) for a in node.args]
            if func.id == "abs" and len(args) == 1:
                return f"fabs({args[0]})"
            if func.id in ("min", "max") and len(args) == 2:
                return f"py_{func.id}({args[0]}, {args[1]})"
            if func.id == "float" and len(args) == 1:
                return f"((double)({args[0]}))"
        if self.helper_function(func):
            helper, args = self._helper_call(node)
            if helper.returns != "scalar":
                what = "nothing" if helper.returns == "void" else f"{helper.returns} numbers"
                raise self._error(node, f"{helper.qualname} returns {what}: call it as a "
                                        "statement or unpack its tuple (a, b = ...)")
            return f"{helper.c_name}({', '.join(args)})"
        raise self._error(node, f"the call {ast.unparse(node)!r}")

    def _declarations(self, skip=()) -> str:
        declared = "".join(f"    double {c};\n" for n, c in self.locals.items() if n not in skip)
        return declared + "".join(f"    int64_t {c};\n" for c in self.counters)


class _Force(_Body):
    """A law's force: (params, committed, trial, deformation, rate) -> out[0..2]."""

    def __init__(self, function, c_name: str, where: str, unit: _Unit):
        super().__init__(function, where, unit)
        node = self.node
        names = [a.arg for a in node.args.args]
        if len(names) != 5:
            raise TranslationError(f"{where}: force takes exactly (params, committed, trial, "
                                   "deformation, rate)")
        # the three arrays and the two scalars, under the law's own names
        self.arrays = dict(zip(names[:3], _ARRAYS))
        self.scalars = {names[3]: "deformation", names[4]: "rate"}
        self.c_name = c_name
        body = _without_docstring(node.body)
        self.lines = self._block(body, 1)
        if not self._returns(body):
            raise self._error(node, "force must end in a return of (force, d force / d "
                                    "deformation, d force / d rate) on every path")

    def writable(self, c_array: str, node) -> None:
        if c_array != "trial":
            raise self._error(node, "only trial[i] may be written")

    def _return(self, node) -> list[str]:
        value = node.value
        helper, args = self._tuple_call(value, 3, node)
        if helper is not None:
            return [f"{helper.c_name}({', '.join(args + ['&out[0]', '&out[1]', '&out[2]'])});",
                    "return;"]
        if not (isinstance(value, ast.Tuple) and len(value.elts) == 3):
            raise self._error(node, "return a tuple of three values")
        parts = [self._expr(v) for v in value.elts]
        return [f"out[0] = {parts[0]};", f"out[1] = {parts[1]};", f"out[2] = {parts[2]};",
                "return;"]

    def c_source(self) -> str:
        declared = self._declarations()
        declared += ("    (void)params; (void)committed; (void)trial; (void)deformation; "
                     "(void)rate;\n")
        body = "\n".join(self.lines)
        # inlined into the element loop of its law group (assembly.c): its result stays in
        # registers, and an open contact costs its first test
        return (f"static PFRAME_INLINE void {self.c_name}(const double *params, "
                f"const double *committed, double *trial,\n"
                f"{' ' * (26 + len(self.c_name))}double deformation, double rate, "
                f"double *out)\n{{\n{declared}{body}\n}}\n")


class _Helper(_Body):
    """A module-level function a law calls: a static C function. Its arguments are numbers
    or arrays (as the first call passes them); it returns nothing, a number, or a tuple
    (written through pointers: ``a, b = helper(...)``, or ``return helper(...)`` from a
    force that returns its three numbers)."""

    def __init__(self, function, c_name: str, array_args: tuple, unit: _Unit, caller):
        self.qualname = f"{function.__module__}.{function.__qualname__}"
        super().__init__(function, f"{self.qualname} (called by {caller.where.split(',')[0]})",
                         unit)
        node = self.node
        self.c_name = c_name
        self.array_args = array_args
        names = [a.arg for a in node.args.args]
        self.arity = len(names)
        if len(names) != len(array_args):
            raise caller.fail(f"{self.qualname} takes {len(names)} arguments, given "
                              f"{len(array_args)}")
        self.params = names
        for name, is_array in zip(names, array_args):
            if is_array:
                self.arrays[name] = name + "_"
            else:
                self.locals[name] = name + "_"  # a number argument: a local, assignable
        self.written_arrays: set[str] = set()
        self.returns = unit.returns(function, caller)
        body = _without_docstring(node.body)
        self.lines = self._block(body, 1)
        if self.returns != "void" and not self._returns(body):
            raise self._error(node, f"{self.qualname} must end in a return on every path")
        self.written = tuple(is_array and name + "_" in self.written_arrays
                             for name, is_array in zip(names, array_args))

    def writable(self, c_array: str, node) -> None:
        self.written_arrays.add(c_array)  # the caller checks that what it passes may be

    def _return(self, node) -> list[str]:
        value = node.value
        if self.returns == "void":
            return ["return;"]
        if self.returns == "scalar":
            return [f"return {self._expr(value)};"]
        helper, args = self._tuple_call(value, self.returns, node)
        if helper is not None:
            return [f"{helper.c_name}({', '.join(args + self._outputs())});", "return;"]
        parts = [self._expr(v) for v in value.elts]
        return [f"*ret{i} = {part};" for i, part in enumerate(parts)] + ["return;"]

    def _outputs(self) -> list[str]:
        return [f"ret{i}" for i in range(self.returns)]

    def c_source(self) -> str:
        arguments = []
        for name, is_array in zip(self.params, self.array_args):
            c = name + "_"
            if is_array:
                const = "" if c in self.written_arrays else "const "
                arguments.append(f"{const}double *{c}")
            else:
                arguments.append(f"double {c}")
        if isinstance(self.returns, int):
            arguments += [f"double *{r}" for r in self._outputs()]
        kind = "double" if self.returns == "scalar" else "void"
        declared = self._declarations(skip=self.params)
        unused = " ".join(f"(void){name}_;" for name in self.params)
        if unused:
            declared += f"    {unused}\n"
        body = "\n".join(self.lines)
        head = f"static PFRAME_INLINE {kind} {self.c_name}("
        return (f"/* {self.qualname} */\n{head}{_wrap(arguments, len(head))})\n"
                f"{{\n{declared}{body}\n}}\n")


def _wrap(arguments: list[str], indent: int, width: int = 96) -> str:
    """Arguments separated by commas, wrapped under the first one within ``width``."""
    lines, line = [], ""
    for i, arg in enumerate(arguments):
        piece = arg + ("," if i < len(arguments) - 1 else "")
        if line and indent + len(line) + 1 + len(piece) > width:
            lines.append(line)
            line = piece
        else:
            line = f"{line} {piece}" if line else piece
    lines.append(line)
    return ("\n" + " " * indent).join(lines)


def translate(law, c_name: str, unit: _Unit | None = None) -> str:
    """The C function ``c_name`` computing ``law.force``, after the helper functions it calls
    (raises TranslationError). With ``unit``, helpers already written for it are not repeated."""
    where = f"{law.kind} law {law.name!r} ({law.__module__}.{law.__qualname__})"
    unit = _Unit() if unit is None else unit
    force = _Force(law.force, c_name, where, unit).c_source()
    return "".join(h + "\n" for h in unit.take()) + force


def _law_functions(laws, unit: _Unit) -> tuple[list[str], dict]:
    """C functions of the laws' force functions (one per distinct Python function: laws that
    share a force share its C), each after the helper functions it calls that ``unit`` has
    not written yet, and law -> C name."""
    done: dict[object, str] = {}
    sources, names = [], {}
    for law in laws:
        function = law.force
        if function not in done:
            python_name = function.__name__ if function.__name__ != "force" else law.name
            done[function] = f"{law.kind}_{python_name}"
            where = f"{law.kind} law {law.name!r} ({law.__module__}.{law.__qualname__})"
            force = _Force(function, done[function], where, unit).c_source()
            sources += unit.take()  # the helpers it calls first
            sources.append(f"/* {law.__module__}.{law.__qualname__}.force */\n{force}")
        names[law] = done[function]
    return sources, names


def laws_c() -> str:
    """The text of c/laws.c."""
    from pframe.laws.registry import builtin_laws

    lines = ["/* Generated by `python -m pframe.kernel.translate` from the built-in laws' Python",
             " * force functions (pframe/laws): do not edit; edit the law and regenerate. */", "",
             '#include "kernel.h"', ""]
    unit = _Unit()
    for kind, function, deformation in (("material", "material_force", "drift"),
                                        ("contact", "contact_force", "penetration")):
        laws = builtin_laws(kind)
        sources, names = _law_functions(laws, unit)
        lines += sources
        macro = "BUILTIN_MATERIALS" if kind == "material" else "BUILTIN_CONTACT_LAWS"
        lines += [f"#define {macro} {len(laws)}", "",
                  f"/* (force, d force / d {deformation}, d force / d rate) of {kind} law `law`"
                  f" into out: ids in registry order, then the plug-ins; for one law's"
                  " force (pframe_law_force, the tests of each law's C translation): the"
                  " element loops call their law's own function (below), not this switch */",
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
        lines += [f"/* every built-in {kind} law as X(id, function): the element loops of",
                  " * assembly.c run a law group with its law's function itself (no switch per",
                  " * element) */", f"#define {kind.upper()}_LAWS(X) \\"]
        lines += [f"    X({law_id}, {names[law]})" + (" \\" if law_id + 1 < len(laws) else "")
                  for law_id, law in enumerate(laws)]
        lines += [""]
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
              "Work": state.Work._fields + state.WORK_PREPARED, "Saved": state.Saved._fields}
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
