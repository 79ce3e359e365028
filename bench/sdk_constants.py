"""The SDK's constants for the Python scripts of bench/ and tests/ (the seed makers, the DataFlash
writer): read from their one declaration in sdk/include/tern/*.hpp, `inline constexpr double NAME =
VALUE;`, so that no script states a physical constant again (tern/math.hpp: gravity, angles;
tern/atmosphere.hpp: the ISA's sea-level pressure and density, its barometric formula's k and n)."""
import os
import re

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def literal(header, name):
    """The value of `name` in sdk/include/tern/`header` as written there (text); ValueError naming
    the header and the constant when it declares no such double."""
    with open(os.path.join(REPO, "sdk", "include", "tern", header)) as f:
        m = re.search(r"constexpr double " + re.escape(name) + r" = ([-+0-9.eE]+);", f.read())
    if not m:
        raise ValueError(f"sdk/include/tern/{header}: no `constexpr double {name}`")
    return m.group(1)


def constant(header, name):
    """The value of `name` in sdk/include/tern/`header`, as a float (literal())."""
    return float(literal(header, name))
