#!/usr/bin/env python3
"""Validates scenario files against scenario/scenario.schema.json (keeps the schema honest).

Usage: check_schema.py SCHEMA FILE_OR_DIR...   Exit 0 valid, 1 invalid, 77 (ctest: skipped)
when python3-jsonschema or python3-yaml is not installed.
"""
import json
import pathlib
import sys

try:
    import jsonschema
    import yaml
except ImportError:
    print("check_schema: python3-jsonschema / python3-yaml not installed: skipped")
    sys.exit(77)


# PyYAML follows YAML 1.1 (on/off/yes/no are booleans); the scenario format is YAML 1.2 core
# like yaml-cpp, so only true/false are booleans here too.
class Yaml12Loader(yaml.SafeLoader):
    pass


Yaml12Loader.yaml_implicit_resolvers = {
    key: [(tag, regexp) for tag, regexp in resolvers if tag != "tag:yaml.org,2002:bool"]
    for key, resolvers in yaml.SafeLoader.yaml_implicit_resolvers.items()
}
Yaml12Loader.add_implicit_resolver(
    "tag:yaml.org,2002:bool", __import__("re").compile(r"^(?:true|false)$"), list("tf"))


def main() -> int:
    schema = json.loads(pathlib.Path(sys.argv[1]).read_text())
    validator = jsonschema.Draft202012Validator(schema)
    files = []
    for arg in sys.argv[2:]:
        path = pathlib.Path(arg)
        files += sorted(path.glob("*.yaml")) if path.is_dir() else [path]
    failed = 0
    for path in files:
        errors = list(validator.iter_errors(yaml.load(path.read_text(), Loader=Yaml12Loader)))
        for error in errors:
            print(f"{path}: {'/'.join(map(str, error.path))}: {error.message}")
        failed += bool(errors)
    print(f"check_schema: {len(files) - failed} of {len(files)} files valid")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
