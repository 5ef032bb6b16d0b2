#!/usr/bin/env python3
"""Checks docs/protocol.md against its example files, its JSON Schemas and the C++ codec.

1. Every ```json block of docs/protocol.md follows an `<!-- example: examples/NAME.json -->`
   line and equals that file byte for byte; every file in docs/examples/ is shown. Links to
   protocol.md#anchors from README.md and docs/*.md name headings that exist, and the relative
   links of protocol.md name files that exist.
2. Every example validates against its schema (docs/examples/MESSAGE[.VARIANT].json →
   docs/schemas/MESSAGE.schema.json), with a small validator of the JSON Schema subset the
   schemas use (standard library only), and with the `jsonschema` package too when it is
   importable (the schemas are then also checked against the draft 2020-12 metaschema).
3. The codec accepts every example (the decoder helper runs decode_<MESSAGE> on it).
4. Mutants of every example, derived from its schema: each required field deleted, each value
   replaced by values of other JSON types, each integer pushed one past its range, each optional
   field deleted, each integer set to its limits, an unknown field added to each object. Schema
   and codec must agree on every one (a mutant that breaks the schema must break the codec, and
   the reverse); required fields deleted and integers out of range must be rejected by both, and
   unknown fields accepted by both.

Usage: check_protocol_doc.py --root SOURCE_DIR --decoder PATH_TO_protocol_doc_decoder
Exit 0 when everything holds, 1 with one line per problem otherwise.
"""
import argparse
import copy
import json
import pathlib
import re
import subprocess
import sys

MESSAGES = ("control_message", "vehicle_response", "vehicle_ocp_shared", "client_ocp_shared")

# ---------------------------------------------------------------------------------------------
# A validator for the subset of JSON Schema (draft 2020-12) the schemas use. Any other keyword
# is an error, so a schema cannot use something this validator would silently ignore.
ANNOTATIONS = {"$schema", "$id", "$comment", "title", "description", "examples", "default", "$defs"}
ASSERTIONS = {"type", "properties", "required", "additionalProperties", "items", "minimum",
              "maximum", "anyOf", "$ref"}


class SchemaError(Exception):
    pass


def json_type_matches(value, name):
    if name == "null":
        return value is None
    if name == "boolean":
        return isinstance(value, bool)
    if name == "object":
        return isinstance(value, dict)
    if name == "array":
        return isinstance(value, list)
    if name == "string":
        return isinstance(value, str)
    if name == "number":
        return isinstance(value, (int, float)) and not isinstance(value, bool)
    if name == "integer":
        return (isinstance(value, int) and not isinstance(value, bool)) or (
            isinstance(value, float) and value.is_integer())
    raise SchemaError(f"unknown type {name!r}")


def resolve(root, ref):
    if not ref.startswith("#/$defs/"):
        raise SchemaError(f"only local #/$defs/ references are supported, got {ref!r}")
    name = ref[len("#/$defs/"):]
    if name not in root.get("$defs", {}):
        raise SchemaError(f"unresolved reference {ref!r}")
    return root["$defs"][name]


def errors(root, schema, value, path="$"):
    """The list of violations of `schema` by `value` (empty: valid)."""
    if schema is True or schema == {}:
        return []
    if schema is False:
        return [f"{path}: no value allowed"]
    unknown = set(schema) - ANNOTATIONS - ASSERTIONS
    if unknown:
        raise SchemaError(f"unsupported keywords {sorted(unknown)} at {path}")
    found = []
    if "$ref" in schema:
        found += errors(root, resolve(root, schema["$ref"]), value, path)
    if "type" in schema:
        names = schema["type"] if isinstance(schema["type"], list) else [schema["type"]]
        if not any(json_type_matches(value, name) for name in names):
            return found + [f"{path}: expected {'/'.join(names)}"]
    if "anyOf" in schema:
        if all(errors(root, branch, value, path) for branch in schema["anyOf"]):
            found.append(f"{path}: matches none of anyOf")
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        if "minimum" in schema and value < schema["minimum"]:
            found.append(f"{path}: below minimum {schema['minimum']}")
        if "maximum" in schema and value > schema["maximum"]:
            found.append(f"{path}: above maximum {schema['maximum']}")
    if isinstance(value, dict):
        properties = schema.get("properties", {})
        for name in schema.get("required", []):
            if name not in value:
                found.append(f"{path}.{name}: required field missing")
        for name, member in value.items():
            if name in properties:
                found += errors(root, properties[name], member, f"{path}.{name}")
            elif "additionalProperties" in schema:
                found += errors(root, schema["additionalProperties"], member, f"{path}.{name}")
    if isinstance(value, list) and "items" in schema:
        for index, element in enumerate(value):
            found += errors(root, schema["items"], element, f"{path}[{index}]")
    return found


def flatten(root, schema):
    """`schema` with its $ref followed (siblings kept), for walking an instance."""
    while isinstance(schema, dict) and "$ref" in schema:
        rest = {k: v for k, v in schema.items() if k != "$ref"}
        schema = {**resolve(root, schema["$ref"]), **rest}
    return schema


def object_branch(root, schema):
    """The object-typed schema a value at `schema` is walked with (through anyOf), or None."""
    schema = flatten(root, schema)
    if not isinstance(schema, dict):
        return None
    if "properties" in schema or "additionalProperties" in schema:
        return schema
    for branch in schema.get("anyOf", []):
        found = object_branch(root, branch)
        if found is not None:
            return found
    return None


def array_items(root, schema):
    schema = flatten(root, schema)
    if not isinstance(schema, dict):
        return None
    if "items" in schema:
        return schema["items"]
    for branch in schema.get("anyOf", []):
        found = array_items(root, branch)
        if found is not None:
            return found
    return None


def integer_range(root, schema):
    """(minimum, maximum) of an integer schema (through anyOf), or None."""
    schema = flatten(root, schema)
    if not isinstance(schema, dict):
        return None
    names = schema.get("type")
    names = names if isinstance(names, list) else [names]
    if "integer" in names and "minimum" in schema and "maximum" in schema:
        return schema["minimum"], schema["maximum"]
    for branch in schema.get("anyOf", []):
        found = integer_range(root, branch)
        if found is not None:
            return found
    return None


# ---------------------------------------------------------------------------------------------
# Mutants: (description, document, must_be_rejected). must_be_rejected None: either verdict, as
# long as schema and codec agree.
OTHER_VALUES = ["text", True, 1.5, 7, {}, [], None]


def set_at(document, path, value):
    mutant = copy.deepcopy(document)
    target = mutant
    for step in path[:-1]:
        target = target[step]
    target[path[-1]] = value
    return mutant


def delete_at(document, path):
    mutant = copy.deepcopy(document)
    target = mutant
    for step in path[:-1]:
        target = target[step]
    del target[path[-1]]
    return mutant


def show(path):
    return "$" + "".join(f"[{step}]" if isinstance(step, int) else f".{step}" for step in path)


def mutants(root, document):
    found = []

    def walk(schema, value, path):
        if path:
            for other in OTHER_VALUES:
                if type(other) is type(value) and other == value:
                    continue
                rejected = bool(errors(root, schema, other))
                found.append((f"{show(path)} = {json.dumps(other)}", set_at(document, path, other),
                               True if rejected else None))
            limits = integer_range(root, schema)
            if limits is not None and isinstance(value, int):
                for limit in limits:   # the limits themselves: schema and codec must agree (accept)
                    found.append((f"{show(path)} = {limit} (limit)", set_at(document, path, limit), None))
                found.append((f"{show(path)} = {limits[0] - 1} (below range)",
                              set_at(document, path, limits[0] - 1), True))
                found.append((f"{show(path)} = {limits[1] + 1} (above range)",
                              set_at(document, path, limits[1] + 1), True))
        if isinstance(value, dict):
            branch = object_branch(root, schema)
            if branch is None:
                return  # user data: any value, nothing inside is checked
            properties = branch.get("properties", {})
            required = branch.get("required", [])
            for name in list(value):
                if name in properties:
                    must = True if name in required else None
                    found.append((f"{show(path + [name])} deleted", delete_at(document, path + [name]), must))
                    walk(properties[name], value[name], path + [name])
                elif "additionalProperties" in branch:
                    walk(branch["additionalProperties"], value[name], path + [name])
            if "additionalProperties" not in branch:
                found.append((f"{show(path)}.x_unknown_field added",
                              set_at(document, path + ["x_unknown_field"], {"added": [1, "two"]}), False))
        elif isinstance(value, list):
            items = array_items(root, schema)
            if items is not None:
                for index, element in enumerate(value):
                    walk(items, element, path + [index])

    walk(root, document, [])
    return found


# ---------------------------------------------------------------------------------------------
def fenced_examples(doc_text):
    """[(line number, named file or None, block text)] for every ```json block."""
    lines = doc_text.split("\n")
    blocks = []
    index = 0
    marker = re.compile(r"^<!-- example: (examples/[A-Za-z0-9_.]+\.json) -->$")
    while index < len(lines):
        if lines[index].strip() == "```json":
            start = index
            end = index + 1
            while end < len(lines) and lines[end].strip() != "```":
                end += 1
            named = None
            if start > 0:
                match = marker.match(lines[start - 1].strip())
                named = match.group(1) if match else None
            blocks.append((start + 1, named, "\n".join(lines[start + 1:end]) + "\n"))
            index = end + 1
        else:
            index += 1
    return blocks


def slug(heading):
    """GitHub's anchor for a Markdown heading."""
    text = re.sub(r"[^\w\- ]", "", heading.strip().lower())
    return text.replace(" ", "-")


def check_links(root, problems):
    """Links into docs/protocol.md#… from the user docs name its headings; its own relative
    links name files that exist."""
    protocol = root / "docs" / "protocol.md"
    text = protocol.read_text(encoding="utf-8")
    anchors, fenced = set(), False
    for line in text.split("\n"):
        fenced = fenced != line.startswith("```")
        if line.startswith("#") and not fenced:
            anchors.add(slug(line.lstrip("#")))
    for doc in [root / "README.md", *sorted((root / "docs").glob("*.md"))]:
        for anchor in re.findall(r"protocol\.md#([\w\-]+)", doc.read_text(encoding="utf-8")):
            if anchor not in anchors:
                problems.append(f"{doc.relative_to(root)}: link to protocol.md#{anchor}, no such heading")
    for target in re.findall(r"\]\(([^)#:]+)(?:#[^)]*)?\)", text):
        if not (protocol.parent / target).exists():
            problems.append(f"docs/protocol.md: link to {target}, no such file")


def run_decoder(decoder, items):
    """items: [(message, json text)] → [(ok, detail)] from the codec."""
    stdin = b"".join(f"{message} {len(text.encode())}\n".encode() + text.encode() for message, text in items)
    result = subprocess.run([decoder], input=stdin, capture_output=True, check=False)
    if result.returncode != 0:
        raise RuntimeError(f"decoder exited {result.returncode}: {result.stderr.decode(errors='replace')}")
    lines = result.stdout.decode().splitlines()
    if len(lines) != len(items):
        raise RuntimeError(f"decoder answered {len(lines)} lines for {len(items)} documents")
    return [(line == "ok", line) for line in lines]


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--root", required=True)
    parser.add_argument("--decoder", required=True)
    args = parser.parse_args()
    root = pathlib.Path(args.root)
    docs = root / "docs"
    problems = []

    try:
        import jsonschema  # optional cross-check (Debian: python3-jsonschema)
    except ImportError:
        jsonschema = None

    # 1. The doc's copies equal the files.
    doc_text = (docs / "protocol.md").read_text(encoding="utf-8")
    shown = set()
    for line, named, block in fenced_examples(doc_text):
        if named is None:
            problems.append(f"docs/protocol.md:{line}: a ```json block without an "
                            "'<!-- example: examples/NAME.json -->' line before it")
            continue
        path = docs / named
        if not path.is_file():
            problems.append(f"docs/protocol.md:{line}: {named} does not exist")
            continue
        shown.add(path.name)
        if path.read_text(encoding="utf-8") != block:
            problems.append(f"docs/protocol.md:{line}: the block differs from docs/{named} (copy the file in)")
    files = sorted((docs / "examples").glob("*.json"))
    for path in files:
        if path.name not in shown:
            problems.append(f"docs/examples/{path.name} is not shown in docs/protocol.md")
    if not files:
        problems.append("no examples in docs/examples/")

    check_links(root, problems)

    # 2.-4. Schemas, codec, mutants.
    schemas = {}
    for message in MESSAGES:
        schema_path = docs / "schemas" / f"{message}.schema.json"
        schemas[message] = json.loads(schema_path.read_text(encoding="utf-8"))
        if jsonschema is not None:
            jsonschema.Draft202012Validator.check_schema(schemas[message])

    checks = []   # (label, message, text, schema verdict: accepted?, must be rejected: True/False/None)
    for path in files:
        message = path.name.split(".")[0]
        if message not in schemas:
            problems.append(f"docs/examples/{path.name}: no schema docs/schemas/{message}.schema.json "
                            f"(name examples MESSAGE[.VARIANT].json, MESSAGE one of {', '.join(MESSAGES)})")
            continue
        schema = schemas[message]
        text = path.read_text(encoding="utf-8")
        document = json.loads(text)
        found = errors(schema, schema, document)
        if found:
            problems.append(f"docs/examples/{path.name} does not validate: {'; '.join(found)}")
        checks.append((f"docs/examples/{path.name}", message, text, not found, False))
        for label, mutant, must in mutants(schema, document):
            accepted = not errors(schema, schema, mutant)
            checks.append((f"docs/examples/{path.name} with {label}", message, json.dumps(mutant), accepted, must))

    results = run_decoder(args.decoder, [(message, text) for _, message, text, _, _ in checks])
    counts = {"examples": 0, "mutants": 0, "rejected": 0}
    for (label, message, text, schema_ok, must), (codec_ok, detail) in zip(checks, results):
        counts["mutants" if " with " in label else "examples"] += 1
        counts["rejected"] += 0 if schema_ok else 1
        if jsonschema is not None:
            library_ok = jsonschema.Draft202012Validator(schemas[message]).is_valid(json.loads(text))
            if library_ok != schema_ok:
                problems.append(f"{label}: jsonschema says {'valid' if library_ok else 'invalid'}, "
                                f"the small validator {'valid' if schema_ok else 'invalid'}")
        if must is False and not schema_ok:
            problems.append(f"{label}: the schema rejects it: {'; '.join(errors(schemas[message], schemas[message], json.loads(text)))}")
        if must is False and not codec_ok:
            problems.append(f"{label}: the codec rejects it: {detail}")
        if must is True and schema_ok:
            problems.append(f"{label}: the schema accepts it, it must not")
        if must is True and codec_ok:
            problems.append(f"{label}: the codec accepts it, it must not")
        if must is None and schema_ok != codec_ok:
            problems.append(f"{label}: schema and codec disagree: schema "
                            f"{'accepts' if schema_ok else 'rejects'}, codec {detail}")

    for problem in problems:
        print(f"FAIL {problem}")
    print(f"protocol doc: {len(files)} example files, {counts['examples']} decoded, {counts['mutants']} mutants "
          f"({counts['rejected']} of them invalid), jsonschema cross-check "
          f"{'on' if jsonschema is not None else 'off (package not installed)'}: "
          f"{'OK' if not problems else f'{len(problems)} problem(s)'}")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
