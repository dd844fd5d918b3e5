"""Copies of a file hidden as a student would hide them, for the copy finder's tests and its
benchmark: every local name renamed, the functions in another order, the comments replaced, or
all three at once. Each takes a random.Random, so a seed gives the same copy again."""

import re

DECLARED = re.compile(r"\b(?:double|int|bool|auto|size_t|std::size_t|Vector|Coordinates|Velocities|char|long|FILE)"
                      r"\s*[&*]*\s+(\w+)\s*(?=[=;,()\[{:])")
FUNCTION = re.compile(r"^(?:static |inline )*[\w:<>,*& ]+?\b\w+\([^;{]*?\)\s*(?:const\s*)?\{\n.*?^\}\n", re.M | re.S)
WORDS = ["alpha", "beta", "gamma", "delta", "omega", "tmp", "value", "thing", "count", "item", "my", "res"]


def renamed(source, rng):
    """Every local name (variables, parameters, helper functions) renamed, consistently."""
    names = sorted(set(DECLARED.findall(source)) - {"main", "n", "rng"}, key=len, reverse=True)
    for name in names:
        new = f"{rng.choice(WORDS)}_{name[::-1]}_{rng.randrange(100)}"
        # (not inside string literals: an error message names the argument as the tests expect)
        source = re.sub(rf'"(?:\\.|[^"\\\n])*"|\b{name}\b', lambda found: found[0] if found[0][0] == '"' else new,
                        source)
    return source


def reordered(source, rng):
    """The functions of one scope in another order, declared first so that the file still
    compiles (each function keeps its text)."""
    functions = list(FUNCTION.finditer(source))
    scopes, scope = [], []
    for before, function in zip([None] + functions, functions):
        if before is not None and re.search(r"^(namespace\b|\})", source[before.end():function.start()], re.M):
            scopes.append(scope)
            scope = []
        scope.append(function)
    scopes.append(scope)
    scope = max(scopes, key=len)
    if len(scope) < 2:
        return source
    order = scope[:]
    while [function.group() for function in order] == [function.group() for function in scope]:
        rng.shuffle(order)
    declarations = "".join(function.group()[:function.group().index("{")].rstrip() + ";\n" for function in scope)
    pieces, at = [], 0
    for place, function in zip(scope, order):
        pieces += [source[at:place.start()], declarations if place is scope[0] else "", function.group()]
        at = place.end()
    return "".join(pieces) + source[at:]


def recommented(source, rng):
    """The comments gone, a few of the student's own put elsewhere."""
    lines = [re.sub(r"\s*//.*$", "", line) for line in re.sub(r"/\*.*?\*/", "", source, flags=re.S).splitlines()]
    for _ in range(max(1, len(lines) // 15)):
        at = rng.randrange(len(lines) + 1)
        lines.insert(at, f"// {rng.choice(WORDS)} step {rng.randrange(10)}")
    return "\n".join(lines) + "\n"


def hidden(source, rng):
    return recommented(reordered(renamed(source, rng), rng), rng)


DISGUISES = {"renamed": renamed, "reordered": reordered, "recommented": recommented, "all three": hidden}
