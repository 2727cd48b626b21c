"""A safe parser for model substitutions such as `magrod check --subs 'B2=B1,c_J=c_H,lambda=0'`.

User input is data, never code: nothing here calls sympify, eval or exec.  The grammar admits only

    subs   := item (',' item)*            item := SYMBOL '=' expr
    expr   := term (('+' | '-') term)*
    term   := unary (('*' | '/') unary)*
    unary  := ('+' | '-') unary | power
    power  := atom (('**' | '^') ('+' | '-')? INTEGER)?
    atom   := NUMBER | SYMBOL | '(' expr ')'

NUMBER is an integer or a decimal (made an exact rational; a rational is written as a quotient), SYMBOL one of
the model's own symbols.  Bounds keep every accepted input cheap: at most MAX_LENGTH characters, MAX_DEPTH
nested parentheses, integer exponents |k| <= MAX_POWER, polynomial degree (numerator plus denominator) at most
MAX_DEGREE, and exact numbers with at most MAX_DIGITS digits.  Anything else raises SubstitutionError with the
position of the offending text.
"""
from __future__ import annotations

import re

import sympy as sp

MAX_LENGTH = 1000
MAX_DEPTH = 16
MAX_POWER = 8
MAX_DEGREE = 16
MAX_DIGITS = 60

_TOKEN = re.compile(r"\s*(?:(?P<num>\d+(?:\.\d*)?|\.\d+)|(?P<name>[A-Za-z_][A-Za-z_0-9]*)|(?P<op>\*\*|[-+*/^(),=]))")


class SubstitutionError(ValueError):
    """Refused substitution text (message names the offending part)."""


def _tokens(text: str) -> list:
    out, pos = [], 0
    text = text.rstrip()
    while pos < len(text):
        m = _TOKEN.match(text, pos)
        if m is None or m.end() == pos:
            raise SubstitutionError(f"unexpected character {text[pos:pos + 1]!r} at position {pos}: only numbers, "
                                    "model symbols, + - * / ** ( ) , = are allowed")
        kind = m.lastgroup
        out.append((kind, m.group(kind), m.start(kind)))
        pos = m.end()
    out.append(("end", "", len(text)))
    return out


class _Parser:
    def __init__(self, text: str, symbols: dict):
        self.toks = _tokens(text)
        self.i = 0
        self.symbols = symbols
        self.depth = 0

    def peek(self):
        return self.toks[self.i]

    def take(self, value=None):
        tok = self.toks[self.i]
        if value is not None and tok[1] != value:
            raise SubstitutionError(f"expected {value!r} at position {tok[2]}, found {tok[1] or 'end of input'!r}")
        self.i += 1
        return tok

    # each rule returns (sympy expression, degree bound)
    def expr(self):
        e, d = self.term()
        while self.peek()[1] in ("+", "-"):
            op = self.take()[1]
            f, g = self.term()
            e, d = (e + f if op == "+" else e - f), max(d, g)
        return e, d

    def term(self):
        e, d = self.unary()
        while self.peek()[1] in ("*", "/"):
            op, pos = self.take()[1:]
            f, g = self.unary()
            if op == "/" and f == 0:
                raise SubstitutionError(f"division by zero at position {pos}")
            e, d = (e * f if op == "*" else e / f), d + g
            self._check(e, d, pos)
        return e, d

    def unary(self):
        if self.peek()[1] in ("+", "-"):
            op = self.take()[1]
            e, d = self.unary()
            return (e if op == "+" else -e), d
        return self.power()

    def power(self):
        base, d = self.atom()
        if self.peek()[1] in ("**", "^"):
            pos = self.take()[2]
            sign = -1 if self.peek()[1] == "-" else 1
            if self.peek()[1] in ("+", "-"):
                self.take()
            kind, val, vpos = self.take()
            if kind != "num" or not val.isdigit():
                raise SubstitutionError(f"exponent at position {vpos} must be an integer literal, got {val!r}")
            k = int(val)
            if k > MAX_POWER:
                raise SubstitutionError(f"exponent {sign * k} at position {vpos} exceeds the bound |k| <= {MAX_POWER}")
            if base == 0 and sign < 0:
                raise SubstitutionError(f"division by zero at position {pos}")
            base, d = base ** (sign * k), d * k
            self._check(base, d, pos)
        return base, d

    def atom(self):
        kind, val, pos = self.take()
        if kind == "num":
            if len(val.replace(".", "")) > MAX_DIGITS:
                raise SubstitutionError(f"number at position {pos} has more than {MAX_DIGITS} digits")
            return sp.Rational(val), 0
        if kind == "name":
            if val not in self.symbols:
                raise SubstitutionError(f"unknown symbol {val!r} at position {pos}; known: "
                                        f"{', '.join(sorted(self.symbols))}")
            return self.symbols[val], 1
        if val == "(":
            self.depth += 1
            if self.depth > MAX_DEPTH:
                raise SubstitutionError(f"more than {MAX_DEPTH} nested parentheses at position {pos}")
            e = self.expr()
            self.take(")")
            self.depth -= 1
            return e
        raise SubstitutionError(f"expected a number, a symbol or '(' at position {pos}, found {val or 'end of input'!r}")

    def _check(self, e, d, pos):
        if d > MAX_DEGREE:
            raise SubstitutionError(f"expression at position {pos} exceeds the degree bound {MAX_DEGREE}")
        for a in sp.preorder_traversal(e):
            if a.is_Rational and max(abs(a.p), a.q) > 10**MAX_DIGITS:
                raise SubstitutionError(f"number at position {pos} exceeds {MAX_DIGITS} digits")

    def items(self) -> dict:
        out = {}
        while True:
            kind, name, pos = self.take()
            if kind != "name" or name not in self.symbols:
                raise SubstitutionError(f"expected a model symbol at position {pos}, found {name or 'end of input'!r}; "
                                        f"known: {', '.join(sorted(self.symbols))}")
            self.take("=")
            value, _ = self.expr()
            if value.has(sp.zoo, sp.nan, sp.oo, -sp.oo):
                raise SubstitutionError(f"value of {name} is not finite")
            out[self.symbols[name]] = value
            if self.peek()[0] == "end":
                return out
            self.take(",")
            if self.peek()[0] == "end":  # a trailing comma is harmless
                return out


def parse(text: str, symbols: dict) -> dict:
    """{symbol: SymPy value} for 'NAME=EXPR, ...' over `symbols` (name -> SymPy symbol); SubstitutionError if
    the text is refused (see the module docstring for the grammar and its bounds)."""
    if not isinstance(text, str):
        raise SubstitutionError(f"expected text, got {type(text).__name__}")
    if len(text) > MAX_LENGTH:
        raise SubstitutionError(f"longer than {MAX_LENGTH} characters")
    if not text.strip():
        raise SubstitutionError("empty: give NAME=VALUE[,NAME=VALUE...]")
    return _Parser(text, symbols).items()
