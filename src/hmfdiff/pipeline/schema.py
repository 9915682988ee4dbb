"""The JSON schema of the pipeline configuration, applied with one-line errors.

`apply_schema(config, schema)` runs, in place and in this order: the refusal of non-finite
numbers; the coercion of numeric-looking strings for the fields the schema types as numbers
(YAML 1.1 reads `1e-1` as a string, and Snakemake's `--config` reads every nested value as a
string); the validation (JSON schema draft 2020-12, with jsonschema); the schema's defaults.
A violation raises ConfigError with one line naming where (case, md run, figure or section),
the field, the value and what is allowed; an unknown field gets the nearest valid name.
`load_yaml_file` reads a YAML file refusing duplicate keys (PyYAML keeps the last silently).
Physics-level checks across fields live in `hmfdiff.pipeline.config`.
"""

from __future__ import annotations

import copy
import difflib
import math
import re
from pathlib import Path

import yaml

from ..errors import ConfigError

__all__ = ["apply_schema", "load_schema", "load_yaml_file", "where_of", "schema_defaults"]

_NUMERIC = re.compile(r"^\s*[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?\s*$")


# ---- YAML ------------------------------------------------------------------------------
class _UniqueKeyLoader(yaml.SafeLoader):
    """SafeLoader that refuses a key given twice in one mapping."""


def _mapping_without_duplicates(loader, node, deep=False):
    loader.flatten_mapping(node)
    first = {}
    for key_node, _ in node.value:
        key = loader.construct_object(key_node, deep=True)
        line = key_node.start_mark.line + 1
        if key in first:
            raise ConfigError(
                f"{loader.name}, line {line}: key {key!r} is given twice (first at line "
                f"{first[key]}); YAML would keep only the last, so the file is refused"
            )
        first[key] = line
    return yaml.SafeLoader.construct_mapping(loader, node, deep=deep)


_UniqueKeyLoader.add_constructor(
    yaml.resolver.BaseResolver.DEFAULT_MAPPING_TAG, _mapping_without_duplicates
)


def load_yaml_file(path):
    """The content of a YAML (or JSON) file; a malformed file or a duplicate key raises a
    one-line ConfigError naming the file and the line."""
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as e:
        raise ConfigError(f"{path}: cannot be read ({e.strerror or e})") from None
    try:
        loader = _UniqueKeyLoader(text)
        loader.name = str(path)
        try:
            return loader.get_single_data()
        finally:
            loader.dispose()
    except yaml.YAMLError as e:
        mark = getattr(e, "problem_mark", None) or getattr(e, "context_mark", None)
        at = f", line {mark.line + 1}, column {mark.column + 1}" if mark else ""
        what = " ".join(str(getattr(e, "problem", None) or e).split())
        raise ConfigError(f"{path}{at}: malformed YAML: {what}") from None


def load_schema(path):
    return yaml.safe_load(Path(path).read_text(encoding="utf-8"))


# ---- walking the schema ----------------------------------------------------------------
def _resolve(ref, root):
    if not ref.startswith("#/"):
        raise ValueError(f"only local $ref are supported, got {ref!r}")
    node = root
    for part in ref[2:].split("/"):
        node = node[part]
    return node


def _branches(schema, root, conditional=True):
    """The schema and every subschema it is composed of ($ref, allOf, and if `conditional`
    also anyOf/oneOf/then/else), each once."""
    out, stack, seen = [], [schema], set()
    while stack:
        s = stack.pop()
        if not isinstance(s, dict) or id(s) in seen:
            continue
        seen.add(id(s))
        out.append(s)
        if "$ref" in s:
            stack.append(_resolve(s["$ref"], root))
        stack.extend(s.get("allOf", []))
        if conditional:
            stack.extend(s.get("anyOf", []) + s.get("oneOf", []))
            stack.extend(s[k] for k in ("then", "else") if k in s)
    return out


def _child(schema, root, key, conditional=True):
    """Subschemas that may apply to instance[key] of an object described by `schema`."""
    out = []
    for s in _branches(schema, root, conditional):
        props = s.get("properties", {})
        if key in props:
            out.append(props[key])
        elif isinstance(s.get("additionalProperties"), dict):
            out.append(s["additionalProperties"])
    return out


def _types(schemas, root):
    return {
        t
        for s in schemas
        for b in _branches(s, root)
        for t in ([b["type"]] if isinstance(b.get("type"), str) else b.get("type", []))
    }


def _field_names(schema, root):
    return sorted({k for s in _branches(schema, root) for k in s.get("properties", {})})


# ---- where, field, value ---------------------------------------------------------------
def where_of(path):
    """Human name of the object at `path` (a list of keys): case 'x', md run 'x', relaxation
    run 'x', figure 'x', a dotted section name, or 'config'."""
    p = [str(k) for k in path]
    if len(p) >= 2 and p[0] == "cases":
        return f"case '{p[1]}'"
    if len(p) >= 3 and p[:2] in (["md", "runs"], ["relaxation", "runs"]):
        return f"{p[0]} run '{p[2]}'"
    if len(p) >= 2 and p[0] == "figures":
        return f"figure '{p[1]}'"
    return ".".join(p) if p else "config"


def _split(path):
    """(path of the enclosing object, field name) for a path into the config; list indices
    stay with their field: ['md', 'fit_window', 0] -> (['md'], 'fit_window[0]')."""
    path = list(path)
    idx = ""
    while path and isinstance(path[-1], int):
        idx = f"[{path.pop()}]" + idx
    if not path:
        return [], idx or "config"
    return path[:-1], f"{path[-1]}{idx}"


def _num(x):
    return repr(float(x)) if isinstance(x, int | float) else repr(x)


def _is_integer(schema):
    t = schema.get("type")
    return "integer" in (t if isinstance(t, list) else [t])


def _allowed(schema):
    """'in (0.0, 1.0)', 'an integer >= 16', 'one of ...', from the keywords of one field."""
    if "enum" in schema:
        return "one of " + ", ".join(repr(v) for v in schema["enum"])
    lo_ex, hi_ex = "exclusiveMinimum" in schema, "exclusiveMaximum" in schema
    lo = schema.get("exclusiveMinimum", schema.get("minimum"))
    hi = schema.get("exclusiveMaximum", schema.get("maximum"))
    if _is_integer(schema):
        if lo is not None and hi is not None:
            return f"an integer >= {lo} and <= {hi}"
        return "an integer" + (f" >= {lo}" if lo is not None else "")
    if lo is None and hi is None:
        return ""
    lb = "(" if lo_ex or lo is None else "["
    rb = ")" if hi_ex or hi is None else "]"
    lo = -math.inf if lo is None else lo
    hi = math.inf if hi is None else hi
    return f"{lb}{_num(lo)}, {_num(hi)}{rb}"


def _type_phrase(t, allowed):
    if t == "number":
        return "a finite number" + (f" in {allowed}" if allowed else "")
    if t == "integer":
        return allowed or "an integer"
    return {"object": "a mapping", "array": "a list", "string": "a string", "null": "null"}.get(
        t, t
    )


def _why(schema):
    d = schema.get("description")
    return f" ({d})" if d else ""


def _nearest(name, schema, root, path):
    """' (did you mean ...?)' from the names allowed here, or from anywhere in the schema."""
    here = _field_names(schema, root)
    low = {k.lower(): k for k in here}
    m = difflib.get_close_matches(str(name).lower(), list(low), n=1, cutoff=0.6)
    if m:
        return f" (did you mean '{low[m[0]]}'?)"
    elsewhere = {}

    def walk(s, where):
        for b in _branches(s, root):
            for k, sub in b.get("properties", {}).items():
                elsewhere.setdefault(k.lower(), (k, ".".join(where)))
                walk(sub, [*where, k])
            if isinstance(b.get("additionalProperties"), dict):
                walk(b["additionalProperties"], [*where, "<name>"])

    walk(root, [])
    m = difflib.get_close_matches(str(name).lower(), list(elsewhere), n=1, cutoff=0.75)
    if m:
        k, where = elsewhere[m[0]]
        return f" (did you mean '{k}', a field of {where or 'the top level'}?)"
    return ""


def _message(err, root):
    """One line for one jsonschema ValidationError."""
    v, inst, sch = err.validator, err.instance, err.schema
    path = list(err.absolute_path)
    if v in ("required", "additionalProperties", "unevaluatedProperties", "oneOf", "minProperties"):
        where = where_of(path)
        if v == "required":
            missing = [k for k in err.validator_value if k not in inst]
            return f"{where}: missing required field(s) {missing}{_why(sch)}"
        if v in ("additionalProperties", "unevaluatedProperties"):
            extra = [k for k in inst if k not in _field_names(sch, root)]
            if not extra:  # additionalProperties with a schema: the value is what is wrong
                return f"{where}: {err.message}"
            k = extra[0]
            allowed = ", ".join(_field_names(sch, root))
            renamed = {
                r: n for b in _branches(sch, root) for r, n in b.get("x-renamed", {}).items()
            }
            if k in renamed:
                return f"{where}: field '{k}' is now called '{renamed[k]}'; allowed: {allowed}"
            return f"{where}: unknown field '{k}'{_nearest(k, sch, root, path)}; allowed: {allowed}"
        if v == "oneOf":
            options = [o["required"][0] for o in err.validator_value if "required" in o]
            given = [k for k in options if k in inst]
            what = sch.get("description", "this entry")
            return (
                f"{where}: {what} takes exactly one of "
                + " or ".join(f"'{k}'" for k in options)
                + f", got {given or 'none'}"
            )
        return f"{where}: must have at least {err.validator_value} entry(ies){_why(sch)}"
    if "propertyNames" in err.relative_schema_path:
        return f"{where_of(path)}: name {inst!r} is not allowed{_why(sch)}"
    parent, field = _split(path)
    where = where_of(parent)
    allowed = _allowed(sch)
    if v == "type":
        wanted = sch["type"] if isinstance(sch["type"], list) else [sch["type"]]
        what = " or ".join(_type_phrase(t, allowed) for t in wanted)
        return f"{where}: field '{field}' = {inst!r} must be {what}{_why(sch)}"
    if v in ("minimum", "maximum", "exclusiveMinimum", "exclusiveMaximum"):
        if _is_integer(sch):
            return f"{where}: field '{field}' = {inst!r} must be {allowed}{_why(sch)}"
        return (
            f"{where}: field '{field}' = {inst!r} is outside the allowed range {allowed}{_why(sch)}"
        )
    if v in ("enum", "const"):
        opts = sch["enum"] if v == "enum" else [sch["const"]]
        return (
            f"{where}: field '{field}' = {inst!r} must be "
            + ("one of " if len(opts) > 1 else "")
            + ", ".join(repr(o) for o in opts)
        )
    if v in ("minItems", "maxItems"):
        return f"{where}: field '{field}' = {inst!r} has the wrong length{_why(sch)}"
    return f"{where}: field '{field}' = {inst!r}: {err.message}{_why(sch)}"


# ---- coercion, validation, defaults ------------------------------------------------------
def _coerce(node, schemas, root, path):
    """Numbers written as strings -> numbers where the schema wants a number or an integer;
    whole floats -> int where it wants an integer; non-finite numbers refused."""
    if isinstance(node, dict):
        for k in list(node):
            node[k] = _coerce(node[k], _child_all(schemas, root, k), root, [*path, k])
        return node
    if isinstance(node, list):
        items = [s["items"] for sc in schemas for s in _branches(sc, root) if "items" in s]
        return [_coerce(x, items, root, [*path, i]) for i, x in enumerate(node)]
    types = _types(schemas, root)
    value = node
    if isinstance(value, str) and types & {"number", "integer"} and _NUMERIC.match(value):
        value = float(value)
    if isinstance(value, str) and "boolean" in types and value.lower() in ("true", "false"):
        value = value.lower() == "true"
    if isinstance(value, float) and not math.isfinite(value):
        parent, field = _split(path)
        raise ConfigError(f"{where_of(parent)}: field '{field}' = {node!r} must be finite")
    if isinstance(value, float) and "integer" in types and value.is_integer():
        return int(value)
    return value


def _child_all(schemas, root, key):
    return [c for s in schemas for c in _child(s, root, key)]


def _document_order(config, path):
    """Sort key placing an error where its path first appears in the config."""
    key, node = [], config
    for k in path:
        if isinstance(node, dict) and k in node:
            key.append(list(node).index(k))
            node = node[k]
        elif isinstance(node, list) and isinstance(k, int) and k < len(node):
            key.append(k)
            node = node[k]
        else:
            key.append(-1)
            break
    return key


def schema_defaults(node, schema, root):
    """Fill in the schema's `default`s, in place: for each object, the defaults of its own
    `properties` (not those of conditional branches), then recursively in its values."""
    if not isinstance(node, dict):
        return
    for s in _branches(schema, root, conditional=False):
        for k, sub in s.get("properties", {}).items():
            if isinstance(sub, dict) and "default" in sub and k not in node:
                node[k] = copy.deepcopy(sub["default"])
    for k, v in node.items():
        for sub in _child(schema, root, k, conditional=False):
            schema_defaults(v, sub, root)


def _consequence(err, root):
    """An unevaluatedProperties error about known fields: it only echoes that a field failed
    its own schema (reported by that field's error)."""
    if err.validator != "unevaluatedProperties" or not isinstance(err.instance, dict):
        return False
    return all(k in _field_names(err.schema, root) for k in err.instance)


def apply_schema(config, schema):
    """Coerce, validate and complete `config` in place; ConfigError (one line) if invalid."""
    import jsonschema

    if not isinstance(config, dict):
        raise ConfigError(f"config: the top level must be a mapping, got {type(config).__name__}")
    _coerce(config, [schema], schema, [])
    validator = jsonschema.Draft202012Validator(schema)
    errors = sorted(
        (e for e in validator.iter_errors(config) if not _consequence(e, schema)),
        key=lambda e: (
            _document_order(config, list(e.absolute_path)),
            -len(e.absolute_path),
            e.validator != "additionalProperties",  # a typo before the field it misses
        ),
    )
    if errors:
        raise ConfigError(_message(errors[0], schema))
    schema_defaults(config, schema, schema)
    return config
