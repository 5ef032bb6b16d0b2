#!/usr/bin/env python3
"""Keeps the README and docs true about what the built programs say of themselves.

  check_docs_facts.py --root SOURCE_DIR --bin BUILD_BIN_DIR

Checks, each against the programs or the source, never against a number written here:
  * every "N cases" said of the vehicle or operator suite equals `ocp_conformance SUITE --list`;
  * the exit-code table of docs/usage.md has exactly the codes of libocp/cli/.../exit_codes.hpp,
    and the README's "Exit codes:" sentence gives each meaning under the table's code for it;
  * the README names every program that is built;
  * every `--option` of a `build/bin/PROGRAM [COMMAND]` line in a README or docs code block is
    in that program's (or command's) --help.
Prints one line per fact (✓ or ✗ with expected against actual); exit 1 when one is wrong.
"""
import argparse
import pathlib
import re
import subprocess
import sys

failures = []


def report(ok, what):
    print(("✓ " if ok else "✗ ") + what)
    if not ok:
        failures.append(what)


def run(args):
    result = subprocess.run(args, capture_output=True, text=True, timeout=60)
    return result.stdout + result.stderr


def doc_files(root):
    return [root / "README.md"] + sorted((root / "docs").glob("*.md"))


def paragraphs(text):
    return [p for p in re.split(r"\n\s*\n", text) if p.strip()]


def check_case_counts(root, bin_dir):
    counts = {}
    for suite in ("vehicle", "operator"):
        listing = run([str(bin_dir / "ocp_conformance"), suite, "--list"])
        counts[suite] = sum(1 for line in listing.splitlines() if re.match(rf"{suite}/\S+\s", line))
    report(all(counts.values()), f"ocp_conformance --list gives cases for both suites ({counts})")
    for path in doc_files(root):
        for paragraph in paragraphs(path.read_text(encoding="utf-8")):
            for match in re.finditer(r"(?<![§./\w])(\d+) cases\b", paragraph):
                before = paragraph[: match.start()]
                named = [(before.rfind(s), s) for s in ("vehicle", "operator") if s in before]
                if not named:
                    continue
                suite = max(named)[1]   # the suite named last before the number
                said = int(match.group(1))
                report(said == counts[suite],
                       f"{path.name}: '{match.group(0)}' of the {suite} suite: expected {counts[suite]}, the doc says {said}")


def check_exit_codes(root):
    header = (root / "libocp/cli/include/ocp/exit_codes.hpp").read_text(encoding="utf-8")
    codes = {int(v) for v in re.findall(r"inline constexpr int exit_\w+ = (\d+);", header)}
    usage = (root / "docs/usage.md").read_text(encoding="utf-8")
    section = usage.split("## Exit codes", 1)[1].split("\n## ", 1)[0]
    rows = {int(m.group(1)): m.group(2) for m in re.finditer(r"^\| (\d+) \| (.*)\|$", section, re.M)}
    report(set(rows) == codes, f"docs/usage.md exit-code table: expected codes {sorted(codes)}, the table has {sorted(rows)}")
    readme = (root / "README.md").read_text(encoding="utf-8")
    sentence = re.search(r"Exit codes: (.*?)\. ", readme.replace("\n", " "))
    report(sentence is not None, "README.md has an 'Exit codes:' sentence")
    if not sentence:
        return
    for code, meaning in re.findall(r"(\d+) ([^,]+)", sentence.group(1)):
        code = int(code)
        report(code in rows, f"README.md exit code {code} ({meaning.strip()}) is in docs/usage.md's table")
        for phrase in ("port in use", "bad command line"):
            if phrase in meaning:
                report(phrase in rows.get(code, ""), f"README.md says '{phrase}' is exit {code}; docs/usage.md's row for {code} says so too")


def check_programs_named(root, bin_dir):
    readme = (root / "README.md").read_text(encoding="utf-8")
    programs = sorted(p.name for p in bin_dir.iterdir() if p.is_file() and p.stat().st_mode & 0o111)
    report(len(programs) >= 6, f"the build has its programs ({', '.join(programs)})")
    for program in programs:
        report(program in readme, f"README.md names {program}")


def check_options(root, bin_dir):
    help_cache = {}
    programs = {p.name for p in bin_dir.iterdir()}
    for path in doc_files(root):
        blocks = re.findall(r"```(?:bash|sh|console)?\n(.*?)```", path.read_text(encoding="utf-8"), re.S)
        for line in "\n".join(blocks).replace("\\\n", " ").splitlines():
            match = re.search(r"build/bin/(\w+)((?: [a-z][\w-]*)?)(.*)", line)
            if not match or match.group(1) not in programs:
                continue
            program, command = match.group(1), match.group(2).strip()
            options_part = match.group(3).split(" -- ", 1)[0].split("#", 1)[0]
            key = (program, command)
            if key not in help_cache:
                help_cache[key] = run([str(bin_dir / program)] + ([command] if command else []) + ["--help"])
            for option in re.findall(r"(?<![\w-])(--[a-z][\w-]*)", options_part):
                report(re.search(rf"(?<![\w-]){re.escape(option)}(?![\w-])", help_cache[key]) is not None,
                       f"{path.name}: `{program}{' ' + command if command else ''} {option}` is in its --help")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--root", required=True, type=pathlib.Path)
    parser.add_argument("--bin", required=True, type=pathlib.Path)
    args = parser.parse_args()
    check_case_counts(args.root, args.bin)
    check_exit_codes(args.root)
    check_programs_named(args.root, args.bin)
    check_options(args.root, args.bin)
    print(f"{len(failures)} wrong" if failures else "every fact checked holds")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
