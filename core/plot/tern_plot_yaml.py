"""tern plot: a small YAML reader, the subset tern's configs and mission files use (Python's
standard library has none; Debian's python3-yaml is not a dependency of tern plot)."""

import math

# ----------------------------------------------------------------------------------------------
# A small YAML reader: the subset tern's configs and mission files use (block maps and
# sequences, "- key: value" items, flow [..] and {..}, quoted and plain scalars, comments).
# Duplicate keys: the last one wins (ROSplane's repeated `wp:` keys are read separately).
# ----------------------------------------------------------------------------------------------

class YamlError(ValueError):
    pass


def _strip_comment(line):
    quote = None
    for i, ch in enumerate(line):
        if quote:
            if ch == quote:
                quote = None
        elif ch in "'\"":
            quote = ch
        elif ch == "#" and (i == 0 or line[i - 1] in " \t"):
            return line[:i]
    return line


def _scalar(s):
    s = s.strip()
    if s == "":
        return None
    if len(s) >= 2 and s[0] == s[-1] and s[0] in "'\"":
        return s[1:-1]
    low = s.lower()
    if low in ("null", "~"):
        return None
    if low in ("true", "yes", "on"):
        return True
    if low in ("false", "no", "off"):
        return False
    if low in (".inf", "+.inf"):
        return math.inf
    if low == "-.inf":
        return -math.inf
    if low == ".nan":
        return math.nan
    try:
        return int(s)
    except ValueError:
        pass
    try:
        return float(s)
    except ValueError:
        return s


class _Flow:
    def __init__(self, text):
        self.s = text
        self.i = 0

    def ws(self):
        while self.i < len(self.s) and self.s[self.i] in " \t\r\n":
            self.i += 1

    def value(self):
        self.ws()
        if self.i >= len(self.s):
            raise YamlError(f"unexpected end of '{self.s}'")
        ch = self.s[self.i]
        if ch == "[":
            self.i += 1
            out = []
            self.ws()
            if self.s[self.i:self.i + 1] == "]":
                self.i += 1
                return out
            while True:
                out.append(self.value())
                self.ws()
                c = self.s[self.i:self.i + 1]
                self.i += 1
                if c == "]":
                    return out
                if c != ",":
                    raise YamlError(f"expected ',' or ']' in '{self.s}'")
        if ch == "{":
            self.i += 1
            out = {}
            self.ws()
            if self.s[self.i:self.i + 1] == "}":
                self.i += 1
                return out
            while True:
                key = self.value()
                self.ws()
                if self.s[self.i:self.i + 1] != ":":
                    raise YamlError(f"expected ':' in '{self.s}'")
                self.i += 1
                out[key] = self.value()
                self.ws()
                c = self.s[self.i:self.i + 1]
                self.i += 1
                if c == "}":
                    return out
                if c != ",":
                    raise YamlError(f"expected ',' or '}}' in '{self.s}'")
        if ch in "'\"":
            end = self.s.find(ch, self.i + 1)
            if end < 0:
                raise YamlError(f"unterminated string in '{self.s}'")
            v = self.s[self.i + 1:end]
            self.i = end + 1
            return v
        j = self.i
        while j < len(self.s) and self.s[j] not in ",]}":
            if self.s[j] == ":" and (j + 1 == len(self.s) or self.s[j + 1] in " \t,]}"):
                break
            j += 1
        v = _scalar(self.s[self.i:j])
        self.i = j
        return v


def _inline(text):
    text = text.strip()
    if text[:1] in "[{":
        f = _Flow(text)
        v = f.value()
        f.ws()
        if f.i != len(text):
            raise YamlError(f"trailing text in '{text}'")
        return v
    return _scalar(text)


def _split_key(content):
    """'key: value' -> (key, value) or None when the line is not a mapping entry."""
    quote = None
    depth = 0
    for i, ch in enumerate(content):
        if quote:
            if ch == quote:
                quote = None
        elif ch in "'\"":
            quote = ch
        elif ch in "[{":
            depth += 1
        elif ch in "]}":
            depth -= 1
        elif ch == ":" and depth == 0 and (i + 1 == len(content) or content[i + 1] in " \t"):
            key = content[:i].strip()
            if len(key) >= 2 and key[0] == key[-1] and key[0] in "'\"":
                key = key[1:-1]
            return key, content[i + 1:].strip()
    return None


def _yaml_lines(text):
    lines = []
    raw = text.splitlines()
    k = 0
    while k < len(raw):
        content = _strip_comment(raw[k]).rstrip()
        k += 1
        if not content.strip() or content.strip() in ("---", "..."):
            continue
        # join a flow collection that continues on the next lines
        while content.count("[") + content.count("{") > content.count("]") + content.count("}") and k < len(raw):
            content += " " + _strip_comment(raw[k]).strip()
            k += 1
        indent = len(content) - len(content.lstrip(" "))
        lines.append([indent, content.strip()])
    return lines


def _block(lines, i, indent):
    """Parses the block starting at lines[i] (indent given); returns (value, next index)."""
    if i >= len(lines):
        return None, i
    is_seq = lines[i][1] == "-" or lines[i][1].startswith("- ")
    if is_seq:
        out = []
        while i < len(lines) and lines[i][0] == indent and (lines[i][1] == "-" or lines[i][1].startswith("- ")):
            rest = lines[i][1][1:].strip()
            if rest == "":
                if i + 1 < len(lines) and lines[i + 1][0] > indent:
                    v, i = _block(lines, i + 1, lines[i + 1][0])
                else:
                    v, i = None, i + 1
                out.append(v)
            elif rest[:1] not in "[{'\"" and _split_key(rest) is not None:
                # "- key: value" starts a map at the column of `key`
                col = indent + (len(lines[i][1]) - len(rest))
                lines[i] = [col, rest]
                v, i = _block(lines, i, col)
                out.append(v)
            else:
                out.append(_inline(rest))
                i += 1
        return out, i
    out = {}
    while i < len(lines) and lines[i][0] == indent:
        kv = _split_key(lines[i][1])
        if kv is None:
            raise YamlError(f"expected 'key: value', got '{lines[i][1]}'")
        key, rest = kv
        if rest == "":
            if i + 1 < len(lines) and (lines[i + 1][0] > indent or
                                       (lines[i + 1][0] == indent and lines[i + 1][1].startswith("- "))):
                v, i = _block(lines, i + 1, lines[i + 1][0])
            else:
                v, i = None, i + 1
        else:
            v = _inline(rest)
            i += 1
        out[key] = v
    return out, i


def yaml_load(text):
    lines = _yaml_lines(text)
    if not lines:
        return None
    v, i = _block(lines, 0, lines[0][0])
    if i != len(lines):
        raise YamlError(f"unexpected indentation at '{lines[i][1]}'")
    return v


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
