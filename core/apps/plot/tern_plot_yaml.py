"""tern plot: YAML through PyYAML (Debian's python3-yaml), read as tern's C++ side (yaml-cpp) reads it.

yaml_load(text) is yaml.safe_load with one addition: floats in YAML 1.2's form (1e-3, 5E+2,
-.5e1), which PyYAML's YAML 1.1 resolver leaves as strings and yaml-cpp reads as numbers.
Duplicate keys: the last one wins (ROSplane's repeated `wp:` keys are split before loading).
Errors: YamlError (a ValueError) with PyYAML's message (line and column)."""

import re

import yaml


class YamlError(ValueError):
    pass


class _Loader(yaml.SafeLoader):
    """SafeLoader that also resolves YAML 1.2 floats with an exponent and no dot."""


_Loader.add_implicit_resolver(
    "tag:yaml.org,2002:float",
    re.compile(r"^[-+]?(?:[0-9][0-9_]*|\.[0-9]+|[0-9][0-9_]*\.[0-9_]*)[eE][-+]?[0-9]+$"),
    list("-+.0123456789"))


def yaml_load(text):
    """The document in `text` (None when empty). Raises YamlError."""
    try:
        return yaml.load(text, Loader=_Loader)  # noqa: S506 (a SafeLoader)
    except yaml.YAMLError as e:
        raise YamlError(str(e).replace("\n", " ")) from None


def top_level_section(text, key):
    """The lines of top-level `key:` (its own line and the indented ones after it)."""
    out = []
    inside = False
    for line in text.splitlines():
        if line[:1] not in ("", " ", "\t", "#"):
            inside = line.startswith(key + ":")
        if inside:
            out.append(line)
    return "\n".join(out)
