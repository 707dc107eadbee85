#!/usr/bin/env python3
"""Synthesizability lint for the HLS kernels (docs/hls.md, "Synthesizability lint").

Fails on what HLS front ends reject: heap, recursion, virtual functions,
exceptions, RTTI, standard containers and streams, loops without a static
bound, floating point in code that runs on the fabric, lambdas, and code that
is not ISO C++14. clang-tidy (.clang-tidy beside this file) covers heap and
recursion, and clang itself, through -fno-exceptions -fno-rtti, covers
exceptions and RTTI. What clang-tidy cannot express is checked here, on
clang's JSON AST.

Only code in files under hls/ and rtl_model/ is reported: the vendors' type
headers and the standard library are the tools' own business.

  hls_lint.py FILE...            lint; exit 0 when clean, 1 on findings
  hls_lint.py --samples FILE...  check the rule samples (hls/lint/bad, good):
                                 every line marked `// expect: RULE[, RULE]`
                                 gets exactly those findings, no other line
                                 gets any, and every rule has a sample
Exit 2 means the lint itself could not run (a tool missing, a crash).
"""

import argparse
import concurrent.futures
import json
import os
import re
import shutil
import subprocess
import sys
from collections import Counter, namedtuple

RULES = {
    "heap": "dynamic allocation (new/delete, malloc family, alloca, std::allocator, VLAs)",
    "recursion": "recursion, direct or mutual",
    "virtual": "virtual functions, polymorphic classes, virtual bases",
    "exception": "throw, try/catch",
    "rtti": "typeid, dynamic_cast",
    "container": "standard containers, strings, smart pointers, std::function",
    "stream": "iostreams, the printf family, FILE I/O",
    "unbounded-loop": "while/do, goto, or a for loop without a compile-time trip count",
    "float": "floating point outside compile-time (constexpr) evaluation",
    "lambda": "lambdas (Intel HLS rejects them in components)",
    "cxx14": "code that is not ISO C++14, the newest standard every HLS front end accepts",
}

# clang-tidy check -> rule. The checks themselves are enabled in .clang-tidy.
TIDY_RULES = {
    "cppcoreguidelines-no-malloc": "heap",
    "cppcoreguidelines-owning-memory": "heap",
    "misc-no-recursion": "recursion",
    "cppcoreguidelines-avoid-goto": "unbounded-loop",
}
# clang's own errors under -fno-exceptions -fno-rtti, as clang-tidy relays them.
TIDY_ERROR_RULES = (
    (re.compile(r"with exceptions disabled"), "exception"),
    (re.compile(r"requires -frtti"), "rtti"),
)
# The AST pass compiles as ISO C++14: clang accepts later features and GNU
# extensions in C++14 mode with a warning, which this makes an error. Each
# error is a "cxx14" finding, except a VLA's, which is heap.
STRICT_FLAGS = ["-pedantic-errors"]
DIAG_RULES = {"-Wvla-extension": "heap"}

_STD = r"(?<![\w])std::(?:__\w+::)*"
TYPE_RULES = (
    (
        "container",
        re.compile(
            _STD + r"(?:vector|basic_string|string|wstring|u16string|u32string|map|multimap"
            r"|set|multiset|list|forward_list|deque|queue|priority_queue|stack|unordered_map"
            r"|unordered_multimap|unordered_set|unordered_multiset|valarray|unique_ptr"
            r"|shared_ptr|weak_ptr|function)\b"
        ),
    ),
    (
        "stream",
        re.compile(
            _STD + r"(?:(?:basic_)?(?:i|o|io)?(?:f|string)?stream"
            r"|(?:basic_)?(?:stream|file|string)buf|(?:basic_)?ios|ios_base)\b"
            r"|\bFILE\b|\b_IO_FILE\b"
        ),
    ),
    ("heap", re.compile(_STD + r"(?:allocator|allocator_traits|pmr::\w+)\b")),
    ("float", re.compile(r"\b(?:float|double|_Float16|__fp16|__bf16|__float128)\b")),
)
# Reported when their declaration is a system one (outside the repository).
STDIO_FUNCTIONS = frozenset(
    "printf fprintf sprintf snprintf vprintf vfprintf vsprintf vsnprintf puts fputs putchar "
    "fputc putc scanf fscanf sscanf getchar fgetc getc fgets fopen freopen fclose fread "
    "fwrite fflush fseek ftell rewind perror".split()
)
ALLOCA_FUNCTIONS = frozenset({"alloca", "__builtin_alloca", "__builtin_alloca_with_align"})
# Also what cppcoreguidelines-owning-memory misses, such as a discarded new.
HEAP_EXPRESSIONS = {"CXXNewExpr": "new-expression", "CXXDeleteExpr": "delete-expression"}

FUNCTION_KINDS = frozenset(
    {"FunctionDecl", "CXXMethodDecl", "CXXConstructorDecl", "CXXDestructorDecl",
     "CXXConversionDecl"}
)
RECORD_KINDS = frozenset(
    {"CXXRecordDecl", "ClassTemplateSpecializationDecl", "ClassTemplatePartialSpecializationDecl"}
)
TEMPLATE_KINDS = frozenset(
    {"FunctionTemplateDecl", "ClassTemplateDecl", "VarTemplateDecl", "TypeAliasTemplateDecl"}
)
TEMPLATE_PARAMETER_KINDS = frozenset(
    {"TemplateTypeParmDecl", "NonTypeTemplateParmDecl", "TemplateTemplateParmDecl"}
)
# Subtrees evaluated at compile time, or not at all.
CONSTANT_KINDS = frozenset(
    {"ConstantExpr", "StaticAssertDecl", "UnaryExprOrTypeTraitExpr", "CXXNoexceptExpr",
     "TemplateArgument", "EnumConstantDecl", "NonTypeTemplateParmDecl"}
)
LOOP_KINDS = frozenset({"ForStmt", "WhileStmt", "DoStmt", "CXXForRangeStmt"})
# A type is reported where it is used, not where an alias names it.
ALIAS_KINDS = frozenset({"TypedefDecl", "TypeAliasDecl"})
# Default arguments belong to their declaration (std::string's allocator, say).
SKIPPED_KINDS = frozenset({"CXXDefaultArgExpr", "CXXDefaultInitExpr", "UsingShadowDecl"})
TRANSPARENT_KINDS = frozenset(
    {"ImplicitCastExpr", "ParenExpr", "MaterializeTemporaryExpr", "ExprWithCleanups",
     "CXXBindTemporaryExpr", "CStyleCastExpr", "CXXStaticCastExpr", "CXXFunctionalCastExpr",
     "SubstNonTypeTemplateParmExpr"}
)
# In an uninstantiated template these stand for what only an instantiation
# knows; the instantiations are checked with the real values.
DEPENDENT_KINDS = frozenset(
    {"DependentScopeDeclRefExpr", "CXXUnresolvedConstructExpr", "UnresolvedLookupExpr",
     "SizeOfPackExpr"}
)
LITERAL_KINDS = frozenset(
    {"IntegerLiteral", "CharacterLiteral", "CXXBoolLiteralExpr", "CXXNullPtrLiteralExpr"}
)
COMPARISONS = frozenset({"<", "<=", ">", ">=", "!="})
FLIPPED = {"<": ">", "<=": ">=", ">": "<", ">=": "<=", "!=": "!="}
ASSIGNING_OPERATORS = frozenset("= += -= *= /= %= &= |= ^= <<= >>= ++ --".split())

Finding = namedtuple("Finding", "path line col rule message source")
# Where the walk is: the node's position, whether it is reported there, whether
# the compiler generated it, the enclosing function (canonical id) and whether
# it is constexpr, whether the code is evaluated at compile time (constant) or
# inside an uninstantiated template (dependent), and the enclosing class's name.
Context = namedtuple(
    "Context", "pos checked implicit func func_constexpr constant dependent record"
)


class ToolError(Exception):
    """The lint could not run (missing tool, crash, unreadable AST)."""


def node_children(node):
    return [c for c in node.get("inner", ()) if isinstance(c, dict)]


def strip(expr):
    """The expression under casts, parentheses and conversion-operator calls."""
    while expr:
        kind = expr.get("kind")
        inner = node_children(expr)
        if kind in TRANSPARENT_KINDS and inner:
            expr = inner[-1] if kind == "SubstNonTypeTemplateParmExpr" else inner[0]
        elif (kind == "CXXMemberCallExpr" and len(inner) == 1
              and inner[0].get("kind") == "MemberExpr"
              and inner[0].get("name", "").startswith("operator ")):
            # x.operator long(): a fixed-width integer converted implicitly.
            object_ = node_children(inner[0])
            expr = object_[0] if object_ else None
        else:
            return expr
    return expr


def operator_call(call):
    """The operator a call names ('<', '++', ...) and its operands."""
    inner = node_children(call)
    callee = strip(inner[0]) if inner else None
    name = None
    if callee and callee.get("kind") == "DeclRefExpr":
        name = callee.get("referencedDecl", {}).get("name")
    elif callee and callee.get("kind") == "MemberExpr":
        name = callee.get("name")
    return (name or "")[len("operator"):], inner[1:]


def class_name(node):
    """'fixed_int' for a node of type 'const odoloc::hls::own::fixed_int<8, false>'."""
    text = node.get("type", {}).get("desugaredQualType") or node.get("type", {}).get("qualType", "")
    text = re.sub(r"<.*", "", text).replace("const ", "").replace("volatile ", "").strip()
    return text.split("::")[-1] or None


class TranslationUnit:
    """One file's AST: walked once, then asked for the findings."""

    def __init__(self, ast, is_checked):
        self.is_checked = is_checked
        self.file = None  # the JSON dumper writes a location's file and line
        self.line = 0  # only when they change, so both are tracked in order
        self.vars = {}  # VarDecl id -> node
        self.functions = {}  # canonical id -> {"constexpr", "path"}
        self.canonical = {}  # function id -> its first declaration's id
        self.virtual_methods = set()
        self.edges = {}  # canonical function -> ids it references at run time
        self.roots = set()  # ids run-time code starts from
        self.constructed = {}  # function (None: namespace scope) -> class names constructed
        self.ctors = {}  # class name -> its constexpr constructors' ids
        self.aliases = {}  # alias name -> the rules its type breaks
        self.candidates = []  # (Finding, Context, detail): decided once the unit is read
        self.findings = []
        self._walk(ast)

    # ---- locations -----------------------------------------------------------
    def _bare(self, loc):
        if "offset" not in loc:
            return None
        self.file = loc.get("file", self.file)
        self.line = loc.get("line", self.line)
        return (self.file, self.line, loc.get("col", 0))

    def _location(self, loc):
        """Updates the tracked file and line; returns the expansion location."""
        if not isinstance(loc, dict):
            return None
        if "spellingLoc" in loc or "expansionLoc" in loc:
            self._bare(loc.get("spellingLoc", {}))
            return self._bare(loc.get("expansionLoc", {}))
        return self._bare(loc)

    def _position(self, node):
        pos = self._location(node.get("loc"))
        span = node.get("range") or {}
        begin = self._location(span.get("begin"))
        self._location(span.get("end"))
        return pos or begin

    # ---- the walk --------------------------------------------------------------
    def _walk(self, root):
        stack = [(root, Context(None, False, False, None, False, False, False, None))]
        while stack:
            node, ctx = stack.pop()
            pos = self._position(node) or ctx.pos
            # Compiler-generated code (implicit members, a lambda's class) is not
            # reported: what it repeats is reported where it is written.
            implicit = ctx.implicit or bool(node.get("isImplicit"))
            checked = bool(pos) and not implicit and self.is_checked(pos[0])
            ctx = ctx._replace(pos=pos, checked=checked, implicit=implicit)
            ctx, pattern = self._visit(node, ctx)
            children = node_children(node)
            for index in range(len(children) - 1, -1, -1):
                child_ctx = ctx._replace(dependent=True) if index == pattern else ctx
                stack.append((children[index], child_ctx))

    def _visit(self, node, ctx):
        """Records what the node says; returns its children's context and the
        index of the child that is a template's (uninstantiated) pattern."""
        kind = node.get("kind", "")
        pattern = None
        if kind in FUNCTION_KINDS:
            ctx = self._function(node, kind, ctx)
        elif kind in TEMPLATE_KINDS:
            # The first child that is not a parameter is the pattern; instantiations follow.
            pattern = next((i for i, c in enumerate(node_children(node))
                            if c.get("kind") not in TEMPLATE_PARAMETER_KINDS), None)
        elif kind == "ClassTemplatePartialSpecializationDecl":
            ctx = ctx._replace(dependent=True)
        if kind in RECORD_KINDS and not node.get("isImplicit"):
            ctx = ctx._replace(record=node.get("name"))
            if ctx.checked:
                self._check_record(node, ctx.pos)
        if kind in CONSTANT_KINDS or (kind == "VarDecl" and node.get("constexpr")):
            ctx = ctx._replace(constant=True)
        if kind == "VarDecl":
            self.vars[node.get("id")] = node
        elif kind in ALIAS_KINDS and ctx.checked:
            broken = self._type_rules(node.get("type"))
            if broken and node.get("name"):
                self.aliases[node["name"]] = set(broken)
        self._references(node, kind, ctx)
        if ctx.checked:
            self._check_node(node, kind, ctx)
        return ctx, pattern

    def _function(self, node, kind, ctx):
        """Indexes a function declaration; returns the context of its body."""
        node_id = node.get("id")
        first = node.get("previousDecl")
        canonical = self.canonical.get(first, first) if first else node_id
        self.canonical[node_id] = canonical
        constexpr = bool(node.get("constexpr"))
        path = ctx.pos[0] if ctx.pos else None
        info = self.functions.setdefault(canonical, {"constexpr": False, "path": path})
        info["constexpr"] = info["constexpr"] or constexpr
        overrides = any(c.get("kind") in {"OverrideAttr", "FinalAttr"} for c in node_children(node))
        if kind in {"CXXMethodDecl", "CXXDestructorDecl"} and (node.get("virtual") or overrides):
            self.virtual_methods.add(node_id)
            if ctx.checked:
                self._report(ctx.pos, "virtual", f"virtual function '{node.get('name')}'")
        if kind == "CXXConstructorDecl" and constexpr and ctx.record:
            self.ctors.setdefault(ctx.record, set()).add(node_id)
        if ctx.checked and not constexpr:
            self.roots.add(canonical)
        return ctx._replace(func=canonical, func_constexpr=constexpr)

    def _references(self, node, kind, ctx):
        """Call-graph edges: which constexpr functions does run-time code call?"""
        if ctx.constant:
            return
        target = None
        if kind == "DeclRefExpr" and node.get("referencedDecl", {}).get("kind") in FUNCTION_KINDS:
            target = node["referencedDecl"].get("id")
        elif kind == "MemberExpr":
            target = node.get("referencedMemberDecl")
        elif kind == "CXXConstructExpr" and (ctx.func or ctx.checked):
            # The JSON names no constructor: every constexpr one of the class counts.
            self.constructed.setdefault(ctx.func, set()).add(class_name(node))
        if target and ctx.func:
            self.edges.setdefault(ctx.func, set()).add(target)
        elif target and ctx.checked:
            self.roots.add(target)

    # ---- rules on single nodes ---------------------------------------------------
    def _report(self, pos, rule, message):
        self.findings.append(Finding(*pos, rule, message, "ast"))

    def _defer(self, pos, rule, message, ctx, detail):
        self.candidates.append((Finding(*pos, rule, message, "ast"), ctx, detail))

    def _check_record(self, node, pos):
        name = node.get("name") or "(anonymous)"
        if node.get("definitionData", {}).get("isPolymorphic"):
            self._report(pos, "virtual", f"polymorphic class '{name}' (needs a vtable)")
        for base in node.get("bases", ()):
            if base.get("isVirtual"):
                base_name = base["type"]["qualType"]
                self._report(pos, "virtual", f"virtual base '{base_name}' of '{name}'")

    def _type_rules(self, type_info):
        """The rules a type breaks, each with the name that breaks it."""
        if not isinstance(type_info, dict):
            return {}
        # The desugared spelling: 'const std::basic_string<char>', not library
        # sugar such as '__alloc_traits<std::allocator<int>, int>::value_type'.
        text = type_info.get("desugaredQualType") or type_info.get("qualType", "")
        broken = {rule: m.group(0) for rule, m in
                  ((rule, pattern.search(text)) for rule, pattern in TYPE_RULES) if m}
        for word in re.findall(r"\w+", text) if self.aliases else ():
            for rule in self.aliases.get(word, ()):
                broken.setdefault(rule, f"{word} (an alias)")
        return broken

    def _check_node(self, node, kind, ctx):
        if kind in SKIPPED_KINDS or kind.endswith("Type"):
            return
        pos = ctx.pos
        if kind not in ALIAS_KINDS:
            for rule, name in self._type_rules(node.get("type")).items():
                written = node["type"].get("qualType")
                if rule == "float":
                    self._defer(pos, rule, f"floating-point type '{written}' in run-time code",
                                ctx, None)
                else:
                    self._report(pos, rule, f"'{name}' in '{written}'")
        if kind == "LambdaExpr":
            self._report(pos, "lambda", "lambda expression")
        elif kind in HEAP_EXPRESSIONS:
            self._report(pos, "heap", HEAP_EXPRESSIONS[kind])
        elif kind == "DeclRefExpr" and node.get("referencedDecl", {}).get("kind") == "FunctionDecl":
            ref = node["referencedDecl"]
            if ref.get("name") in ALLOCA_FUNCTIONS:
                self._report(pos, "heap", f"'{ref['name']}' (stack allocation of run-time size)")
            elif ref.get("name") in STDIO_FUNCTIONS:
                self._defer(pos, "stream", f"C stdio function '{ref['name']}'", ctx, ref.get("id"))
        elif kind == "CXXMemberCallExpr" and node_children(node):
            member = node_children(node)[0]
            if member.get("referencedMemberDecl"):
                self._defer(pos, "virtual", f"call of virtual function '{member.get('name')}'", ctx,
                            member["referencedMemberDecl"])
        elif kind in LOOP_KINDS:
            self._defer(pos, "unbounded-loop", "", ctx, node)

    # ---- decisions that need the whole unit -------------------------------------
    def _runtime_functions(self):
        """Canonical ids of the functions run-time code can reach."""
        ctors = {name: {self.canonical.get(i, i) for i in ids} for name, ids in self.ctors.items()}

        def callees(func):
            yield from (self.canonical.get(t, t) for t in self.edges.get(func, ()))
            for name in self.constructed.get(func, ()):
                yield from ctors.get(name, ())

        reached = set()
        queue = [self.canonical.get(r, r) for r in self.roots] + list(callees(None))
        while queue:
            func = queue.pop()
            if func not in reached:
                reached.add(func)
                queue.extend(callees(func))
        return reached

    def results(self):
        runtime = self._runtime_functions()
        findings = list(self.findings)
        for finding, ctx, detail in self.candidates:
            # Compile-time code: constant contexts, and constexpr functions that no
            # run-time code calls (or that are an uninstantiated template).
            compile_time = ctx.constant or (
                ctx.func_constexpr and (ctx.dependent or ctx.func not in runtime))
            if finding.rule == "float" and not compile_time:
                findings.append(finding)
            elif finding.rule == "stream":
                path = self.functions.get(self.canonical.get(detail, detail), {}).get("path")
                if not path or not self.is_checked(path):
                    findings.append(finding)
            elif finding.rule == "virtual" and detail in self.virtual_methods:
                findings.append(finding)
            elif finding.rule == "unbounded-loop" and not compile_time:
                problem = self._loop_problem(detail, ctx.dependent)
                if problem:
                    findings.append(finding._replace(message=problem))
        return findings

    # ---- loops -------------------------------------------------------------------
    def _loop_problem(self, loop, dependent):
        """Why the loop has no compile-time trip count, or None."""
        kind = loop["kind"]
        inner = loop.get("inner", [])  # with {} for an absent part
        if kind in {"WhileStmt", "DoStmt"}:
            cond = strip(node_children(loop)[0 if kind == "WhileStmt" else -1])
            if cond and cond.get("kind") in LITERAL_KINDS and cond.get("value") in {False, "0"}:
                return None  # do { ... } while (false)
            return f"'{'while' if kind == 'WhileStmt' else 'do'}' loop: no compile-time trip count"
        if kind == "CXXForRangeStmt":
            # The range's type: the hidden __range variable's, or in an uninstantiated
            # template (where that is 'auto &&') its initialiser's.
            ranges = node_children(inner[1]) if len(inner) > 1 and inner[1] else []
            nodes = ranges[:1] + [strip(c) for c in node_children(ranges[0])] if ranges else []
            types = [n.get("type", {}) for n in nodes if n]
            texts = [t.get("desugaredQualType") or t.get("qualType", "") for t in types]
            size = r"\[\w+\]" if dependent else r"\[\d+\]"
            if any(re.search(size, t) or re.search(r"\bstd::array<", t) for t in texts):
                return None
            return f"range-for over '{texts[-1] if texts else '?'}': not a fixed-size array"
        if len(inner) != 5:
            return "'for' loop of an unexpected shape"
        init, _, cond, inc, body = inner
        if not (init.get("kind") == "DeclStmt" and len(node_children(init)) == 1):
            return "'for' loop: declare one counter in it: for (int i = C0; i < C1; ++i)"
        counter = node_children(init)[0]
        name = counter.get("name")
        start = node_children(counter)[-1] if node_children(counter) else None
        if counter.get("kind") != "VarDecl" or not self._constant(start, dependent):
            return f"'for' loop: the counter '{name}' does not start at a constant"
        comparison = self._comparison(cond, counter.get("id")) if cond else None
        if not comparison:
            return f"'for' loop: the condition is not '{name} <comparison> bound'"
        op, bound = comparison
        if not self._constant(bound, dependent):
            return f"'for' loop: the bound on '{name}' is not a compile-time constant"
        step = self._step(inc, counter.get("id"), dependent) if inc else None
        if step is None:
            return f"'for' loop: the step is not ++, --, += C or -= C on '{name}'"
        if (step > 0 and op in {">", ">="}) or (step < 0 and op in {"<", "<="}):
            return f"'for' loop: the step moves '{name}' away from its bound"
        if self._assigns(body, counter.get("id")):
            return f"'for' loop: the body changes the counter '{name}'"
        return None

    @staticmethod
    def _refers_to(expr, var_id):
        expr = strip(expr)
        return bool(expr) and expr.get("kind") == "DeclRefExpr" and \
            expr.get("referencedDecl", {}).get("id") == var_id

    def _comparison(self, cond, var_id):
        """(operator, bound) for 'var op bound' or 'bound op var', else None."""
        cond = strip(cond)
        if cond.get("kind") == "BinaryOperator":
            op, args = cond.get("opcode"), node_children(cond)
        elif cond.get("kind") == "CXXOperatorCallExpr":
            op, args = operator_call(cond)
        else:
            return None
        if op not in COMPARISONS or len(args) != 2:
            return None
        if self._refers_to(args[0], var_id):
            return op, args[1]
        if self._refers_to(args[1], var_id):
            return FLIPPED[op], args[0]
        return None

    def _step(self, inc, var_id, dependent):
        """+1 for an increasing counter, -1 for a decreasing one, None otherwise."""
        kind = inc.get("kind")
        if kind in {"UnaryOperator", "CompoundAssignOperator"}:
            op, args = inc.get("opcode"), node_children(inc)
        elif kind == "CXXOperatorCallExpr":
            op, args = operator_call(inc)
        else:
            return None
        if op not in {"++", "--", "+=", "-="} or not args or not self._refers_to(args[0], var_id):
            return None
        if op in {"+=", "-="} and (len(args) != 2 or not self._constant(args[1], dependent)):
            return None
        return 1 if op in {"++", "+="} else -1

    def _assigns(self, body, var_id):
        """Whether the body assigns, increments or takes the address of the counter."""
        stack = [body] if body else []
        while stack:
            node = stack.pop()
            kind = node.get("kind")
            target = None
            op = node.get("opcode")
            assigns = op in ASSIGNING_OPERATORS and kind in {"BinaryOperator",
                                                             "CompoundAssignOperator"}
            if assigns or (kind == "UnaryOperator" and op in {"++", "--", "&"}):
                target = node_children(node)[0]
            elif kind == "CXXOperatorCallExpr":
                op, args = operator_call(node)
                target = args[0] if op in ASSIGNING_OPERATORS and args else None
            if target is not None and self._refers_to(target, var_id):
                return True
            stack.extend(node_children(node))
        return False

    def _constant(self, expr, dependent, depth=0):
        """Whether expr is a compile-time constant (a conservative subset of C++'s rules)."""
        if not expr or depth > 50:
            return False
        kind = expr.get("kind")
        inner = node_children(expr)

        def all_constant(nodes):
            return all(self._constant(n, dependent, depth + 1) for n in nodes)

        if kind in LITERAL_KINDS or kind in {"ConstantExpr", "UnaryExprOrTypeTraitExpr",
                                             "SubstNonTypeTemplateParmExpr"}:
            return True
        if kind in DEPENDENT_KINDS:
            return dependent
        if kind in TRANSPARENT_KINDS or kind in {"UnaryOperator", "BinaryOperator",
                                                 "ConditionalOperator", "InitListExpr",
                                                 "CXXConstructExpr", "CXXTemporaryObjectExpr"}:
            return expr.get("opcode") not in ASSIGNING_OPERATORS and all_constant(inner)
        if kind == "DeclRefExpr":
            ref = expr.get("referencedDecl", {})
            if ref.get("kind") in {"EnumConstantDecl", "NonTypeTemplateParmDecl"}:
                return True
            return ref.get("kind") == "VarDecl" and \
                self._constant_var(ref.get("id"), dependent, depth)
        if kind == "MemberExpr":
            target = expr.get("referencedMemberDecl")
            if target in self.vars:  # a static data member
                return self._constant_var(target, dependent, depth)
            return all_constant(inner)  # a field of a constant object
        if kind in {"CallExpr", "CXXMemberCallExpr", "CXXOperatorCallExpr"} and inner:
            callee, args = strip(inner[0]), inner[1:]
            if callee.get("kind") in DEPENDENT_KINDS:
                return dependent and all_constant(args)
            target = None
            if callee.get("kind") == "DeclRefExpr":
                target = callee.get("referencedDecl", {}).get("id")
            elif callee.get("kind") == "MemberExpr":
                target = callee.get("referencedMemberDecl")
                args = node_children(callee) + args  # the object is an argument too
            function = self.functions.get(self.canonical.get(target, target), {})
            return function.get("constexpr", False) and all_constant(args)
        return False

    def _constant_var(self, var_id, dependent, depth):
        var = self.vars.get(var_id)
        if not var:
            return False
        if var.get("constexpr"):
            return True
        # A const integer with a constant initialiser is a constant expression too.
        init = node_children(var)[-1] if node_children(var) else None
        return var.get("type", {}).get("qualType", "").startswith("const ") and \
            var.get("init") is not None and self._constant(init, dependent, depth + 1)


class Linter:
    def __init__(self, root, clang, clang_tidy, include_dirs):
        self.root = os.path.realpath(root)
        self.clang = self._tool(clang)
        self.clang_tidy = self._tool(clang_tidy)
        self.tidy_config = os.path.join(os.path.dirname(os.path.realpath(__file__)), ".clang-tidy")
        self.checked_dirs = tuple(os.path.join(self.root, d) + os.sep for d in ("hls", "rtl_model"))
        includes = [os.path.join(self.root, "hls", "include"),
                    os.path.join(self.root, "rtl_model", "include")] + list(include_dirs)
        # How the lint compiles a kernel: C++14, the project's own integer types
        # (no vendor header needed), __SYNTHESIS__ defined as the HLS tools do.
        self.flags = ["-std=c++14", "-DODOLOC_HLS_TYPES=0", "-D__SYNTHESIS__",
                      "-Wno-unknown-pragmas"] + [f"-I{os.path.realpath(d)}" for d in includes]
        self._checked = {}

    @staticmethod
    def _tool(name):
        path = shutil.which(name)
        if not path:
            raise ToolError(f"{name} not found (scripts/setup-debian.sh installs clang and "
                            "clang-tidy)")
        return path

    def is_checked(self, path):
        if path not in self._checked:
            real = os.path.realpath(path) if path and not path.startswith("<") else ""
            self._checked[path] = real.startswith(self.checked_dirs)
        return self._checked[path]

    def lint(self, path):
        path = os.path.realpath(path)
        header_filter = "^(" + "|".join(re.escape(d) for d in self.checked_dirs) + ")"
        tidy = subprocess.Popen(
            [self.clang_tidy, "--quiet", f"--config-file={self.tidy_config}",
             f"--header-filter={header_filter}", path, "--", *self.flags, "-fno-exceptions",
             "-fno-rtti"],
            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        try:
            ast = subprocess.run(
                [self.clang, "-fsyntax-only", "-Xclang", "-ast-dump=json", *self.flags,
                 *STRICT_FLAGS, path],
                stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, timeout=600,
                check=False)
            tidy_out, tidy_err = tidy.communicate(timeout=600)
        finally:
            if tidy.poll() is None:
                tidy.kill()
        if tidy.returncode not in (0, 1):  # 1: findings or compile errors
            raise ToolError(f"clang-tidy failed on {path} ({tidy.returncode}):\n{tidy_err}")
        if ast.returncode < 0 or not ast.stdout:
            raise ToolError(f"clang failed on {path} ({ast.returncode}):\n{ast.stderr}")
        try:
            tree = json.loads(ast.stdout)
        except json.JSONDecodeError as error:
            raise ToolError(f"clang's AST of {path} is not JSON: {error}") from error
        findings = self._tidy_findings(tidy_out) + self._compile_errors(ast.stderr)
        return dedupe(findings + TranslationUnit(tree, self.is_checked).results())

    def _tidy_findings(self, output):
        pattern = re.compile(r"^(.+?):(\d+):(\d+): (?:warning|error): (.*) \[([\w.,-]+)\]$")
        findings = []
        for match in filter(None, map(pattern.match, output.splitlines())):
            path, row, col, message, checks = match.groups()
            if not self.is_checked(path):
                continue
            for check in checks.split(","):
                rule = TIDY_RULES.get(check)
                if check == "clang-diagnostic-error":
                    # Other compiler errors come from the AST pass, which is stricter.
                    rule = next((r for p, r in TIDY_ERROR_RULES if p.search(message)), None)
                if rule:
                    findings.append(Finding(path, int(row), int(col), rule, message,
                                            f"clang-tidy {check}"))
        return findings

    @staticmethod
    def _compile_errors(stderr):
        """The AST pass's errors: the code is not ISO C++14 (or has a VLA)."""
        pattern = re.compile(r"^(.+?):(\d+):(\d+): (?:fatal )?error: (.*?)(?: \[(-W[^\]]+)\])?$")
        findings = []
        for match in filter(None, map(pattern.match, stderr.splitlines())):
            path, row, col, message, flags = match.groups()
            rule = DIAG_RULES.get((flags or "").split(",")[-1], "cxx14")
            findings.append(Finding(path, int(row), int(col), rule, message, "clang"))
        return findings

    def relative(self, path):
        return os.path.relpath(path, self.root) if path.startswith(self.root + os.sep) else path


def dedupe(findings):
    """One finding per line and rule: clang-tidy and the AST pass may both see it."""
    unique = {}
    for f in findings:
        f = f._replace(path=os.path.realpath(f.path))
        unique.setdefault((f.path, f.line, f.rule), f)
    return sorted(unique.values(), key=lambda f: (f.path, f.line, f.col, f.rule))


def lint_main(linter, results):
    findings = [f for _, file_findings in results for f in file_findings]
    for f in findings:
        print(f"{linter.relative(f.path)}:{f.line}:{f.col}: [{f.rule}] {f.message} ({f.source})")
    if not findings:
        print(f"hls_lint: {len(results)} file(s) clean")
        return 0
    by_rule = sorted(Counter(f.rule for f in findings).items())
    counts = ", ".join(f"{rule} {n}" for rule, n in by_rule)
    print(f"hls_lint: {len(findings)} finding(s) in {len({f.path for f in findings})} file(s): "
          f"{counts}")
    print("hls_lint: the rules and how to fix each: docs/hls.md, 'Synthesizability lint'")
    return 1


EXPECT = re.compile(r"//.*\bexpect:\s*([\w-]+(?:\s*,\s*[\w-]+)*)")


def expectations(path):
    """The (line, rule) pairs a sample marks with `// expect: RULE[, RULE]`."""
    expected = set()
    with open(path, encoding="utf-8") as source:
        for number, text in enumerate(source, 1):
            match = EXPECT.search(text)
            if match:
                expected |= {(number, rule.strip()) for rule in match.group(1).split(",")}
    unknown = sorted({rule for _, rule in expected} - set(RULES))
    if unknown:
        raise ToolError(f"{path}: unknown rule(s) after 'expect:': {', '.join(unknown)}")
    return expected


def samples_main(linter, results):
    problems, covered = 0, set()
    for path, findings in results:
        expected = expectations(path)
        covered |= {rule for _, rule in expected}
        real = os.path.realpath(path)
        unexpected = [f for f in findings if f.path != real or (f.line, f.rule) not in expected]
        missing = expected - {(f.line, f.rule) for f in findings if f.path == real}
        if missing or unexpected:
            problems += 1
            print(f"FAIL {linter.relative(real)}")
            for line, rule in sorted(missing):
                print(f"  line {line}: [{rule}] expected, not reported")
            for f in unexpected:
                print(f"  unexpected: {linter.relative(f.path)}:{f.line}: [{f.rule}] {f.message}")
        else:
            rules = ", ".join(sorted({rule for _, rule in expected})) or "clean, as expected"
            print(f"ok   {linter.relative(real)}: {rules}")
    uncovered = sorted(set(RULES) - covered)
    if uncovered:
        problems += 1
        print(f"FAIL no sample shows rule(s): {', '.join(uncovered)}")
    print(f"hls_lint_rules: {len(results)} sample(s), {problems} problem(s)")
    return 1 if problems else 0


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n", 1)[0])
    parser.add_argument("files", nargs="+")
    parser.add_argument("--samples", action="store_true", help="check the rule samples")
    parser.add_argument("--root", default=os.path.join(os.path.dirname(__file__), "..", ".."),
                        help="the repository (default: two levels above this script)")
    parser.add_argument("--clang", default="clang++")
    parser.add_argument("--clang-tidy", default="clang-tidy")
    parser.add_argument("-I", dest="include_dirs", action="append", default=[],
                        help="an extra include directory (the build's generated headers)")
    parser.add_argument("-j", "--jobs", type=int, default=min(2, os.cpu_count() or 1))
    args = parser.parse_args()
    try:
        linter = Linter(args.root, args.clang, args.clang_tidy, args.include_dirs)
        with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
            results = list(zip(args.files, pool.map(linter.lint, args.files)))
        return samples_main(linter, results) if args.samples else lint_main(linter, results)
    except (ToolError, OSError, subprocess.SubprocessError) as error:
        print(f"hls_lint: cannot run: {error}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
