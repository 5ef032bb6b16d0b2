#!/usr/bin/env python3
"""Command-line errors name what is wrong, and output paths are checked before a run starts.

  cli_errors.py BIN_DIR

Each row runs one built program as a user would and checks its exit code, that its output names
the real mistake (and never blames the wrong words), and that it ends within the row's bound:
an output path that cannot be written is refused when the command line is read, not after a run
of `--duration-s 600`. Prints ✓/✗ per row with expected against actual; exit 1 when one fails.
"""
import pathlib
import socket
import subprocess
import sys
import tempfile

BIN = pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else None
failures = []


def check(name, args, code, says=(), never=(), limit_s=60):
    try:
        result = subprocess.run([str(BIN / args[0])] + args[1:], capture_output=True, text=True, timeout=limit_s,
                                stdin=subprocess.DEVNULL)
    except subprocess.TimeoutExpired:
        failures.append(name)
        print(f"✗ {name}: expected exit {code} within {limit_s} s, still running")
        return
    output = result.stdout + result.stderr
    problems = []
    if result.returncode != code:
        problems.append(f"exit {result.returncode}, expected {code}")
    problems += [f"missing {text!r}" for text in says if text not in output]
    problems += [f"should not say {text!r}" for text in never if text in output]
    if problems:
        failures.append(name)
        print(f"✗ {name}: {'; '.join(problems)}\n    output: {output.strip()[:600]!r}")
    else:
        print(f"✓ {name}")


def main():
    if BIN is None:
        print(__doc__)
        return 2
    scratch = pathlib.Path(tempfile.mkdtemp(prefix="ocp_cli_errors_"))
    missing_dir = str(scratch / "no" / "such" / "dir")
    # A path below a plain file: no folder can be made there, even by root (CI runs as root).
    plain_file = scratch / "plain-file"
    plain_file.write_text("x")
    not_writable = str(plain_file)

    # An unknown option or command is named, with the nearest known one.
    check("conformance: --case is named, --cases suggested",
          ["ocp_conformance", "vehicle", "--case", "vehicle/2/2", "--", "node", "c.js", "127.0.0.1:{port}"], 2,
          says=["unknown option '--case'", "did you mean '--cases'?"], never=["were not expected", "c.js"])
    check("conformance: vehicl suggests vehicle", ["ocp_conformance", "vehicl"], 2,
          says=["unknown command 'vehicl'", "did you mean 'vehicle'?"], never=["A subcommand is required"])
    check("bench: --duraton-s is named, --duration-s suggested",
          ["ocp_bench", "loop", "--duraton-s", "1", "--", "true"], 2,
          says=["unknown option '--duraton-s'", "did you mean '--duration-s'?"], never=["were not expected"])
    check("campaign: its own name on errors, no build path in a usage line", ["ocp_campaign", "run", "--wrolds", "3"], 2,
          says=["ocp_campaign: unknown option '--wrolds'", "did you mean '--worlds'?"], never=["Usage: ", "build/bin"])
    check("campaign: runn suggests run", ["ocp_campaign", "runn"], 2, says=["did you mean 'run'?"])
    check("scenario: --sed suggests --seed", ["ocp_scenario", "run", "x.yaml", "--sed", "3"], 2,
          says=["unknown option '--sed'", "did you mean '--seed'?"])
    check("streamer_sim: --link-dely-ms suggests --link-delay-ms", ["streamer_sim", "--link-dely-ms", "5"], 2,
          says=["did you mean '--link-delay-ms'?"])
    check("a value that starts with '-' is the option's, not an unknown option", ["streamer_sim", "--link-delay-ms", "-inf"], 2,
          says=["--link-delay-ms"], never=["unknown option"])
    check("a known option with a bad value keeps CLI11's own message", ["ocp_campaign", "run", "--worlds", "0"], 2,
          says=["--worlds"], never=["unknown option"])

    # A missing input file gives the system's reason.
    check("campaign: a missing profile says why", ["ocp_campaign", "run", "--profile", str(scratch / "missing.yaml")], 2,
          says=["ocp_campaign run: ", "missing.yaml: ", "No such file or directory"], never=[":0:0:"])

    # Output paths are checked before anything runs.
    check("bench loop: --json in a missing folder, before measuring",
          ["ocp_bench", "loop", "--duration-s", "600", "--json", missing_dir + "/x.json", "--", "true"], 2,
          says=["does not exist"], limit_s=20)
    check("bench loop: --html below a plain file",
          ["ocp_bench", "loop", "--duration-s", "600", "--html", not_writable + "/x.html", "--", "true"], 2, limit_s=20)
    check("bench fleet: --svg in a missing folder", ["ocp_bench", "fleet", "--svg", missing_dir + "/f.svg"], 2,
          says=["does not exist"], limit_s=20)
    check("conformance: --junit in a missing folder",
          ["ocp_conformance", "vehicle", "--junit", missing_dir + "/j.xml", "--", "true"], 2, says=["does not exist"], limit_s=20)
    check("conformance: --out where no folder can be made",
          ["ocp_conformance", "vehicle", "--out", not_writable + "/out", "--", "true"], 2, limit_s=20)
    check("scenario: --out where no folder can be made",
          ["ocp_scenario", "run", "x.yaml", "--out", not_writable + "/out"], 2, says=["--out"], limit_s=20)
    check("scenario: --junit in a missing folder", ["ocp_scenario", "run", "x.yaml", "--junit", missing_dir + "/j.xml"], 2,
          says=["does not exist"], limit_s=20)
    check("campaign: --out where no folder can be made", ["ocp_campaign", "run", "--out", not_writable + "/out"], 2, limit_s=20)
    check("campaign merge: --out where no folder can be made", ["ocp_campaign", "merge", "x", "--out", not_writable + "/m"], 2,
          limit_s=20)
    check("streamer_sim: --wire-log in a missing folder",
          ["streamer_sim", "--duration-s", "600", "--wire-log", missing_dir + "/w.jsonl"], 2, says=["does not exist"], limit_s=20)
    check("an output path that is a folder", ["ocp_bench", "fleet", "--json", str(scratch)], 2, says=["is a folder"], limit_s=20)

    # A busy port names this program's own option.
    with socket.socket() as busy:
        busy.bind(("127.0.0.1", 0))
        busy.listen()
        port = str(busy.getsockname()[1])
        check("bench loop: a busy port names --port", ["ocp_bench", "loop", "--port", port, "--duration-s", "1"], 2,
              says=["--port N"], never=["--plugin-param"], limit_s=20)

    # A client that exits before it connects is shown by its last lines, without --out.
    check("conformance: a client that exits at once shows its last lines",
          ["ocp_conformance", "vehicle", "--cases", "vehicle/2/1", "--", "sh", "-c", "echo boom-from-the-client; exit 3"], 2,
          says=["boom-from-the-client", "exited with code 3", "HARNESS ERROR"], never=["0 cases in"], limit_s=30)

    # --time and the options of launched clients: a range, a clear error, exit 2 (issue #38).
    ext = scratch / "ext.yaml"
    ext.write_text("seed: 1\nduration: 1s\nworld:\n  vehicles:\n    - name: truck-1\n      in_process_client: false\n"
                   "expect:\n  faults:\n    - {fault: InvalidMac, never: true}\n")
    for tool, args in (("ocp_conformance", ["vehicle"]), ("ocp_scenario", ["run", str(ext)]), ("ocp_campaign", ["run"]),
                       ("ocp_campaign", ["slurm", "--print-only"])):
        check(f"{tool} {args[0]}: --time warp is named", [tool] + args + ["--time", "warp", "--", "true"], 2,
              says=["--time"], limit_s=20)
    check("conformance: --time virtual without a launched client",
          ["ocp_conformance", "vehicle", "--time", "virtual"], 2, says=["--time virtual launches the client"], limit_s=20)
    for value in ("0", "-1", "nan", "inf", ""):
        check(f"scenario: --connect-timeout-s {value!r}",
              ["ocp_scenario", "run", str(ext), "--time", "real", "--connect-timeout-s", value, "--", "true"], 2,
              says=["--connect-timeout-s"], limit_s=20)
        check(f"scenario: --world-timeout {value!r}", ["ocp_scenario", "run", str(ext), "--world-timeout", value, "--", "true"], 2,
              says=["--world-timeout"], limit_s=20)
        check(f"campaign slurm: --max-world-seconds {value!r}",
              ["ocp_campaign", "slurm", "--print-only", "--max-world-seconds", value], 2, says=["--max-world-seconds"], limit_s=20)
    check("scenario: an empty --operator-client", ["ocp_scenario", "run", str(ext), "--operator-client", " ", "--", "true"], 2,
          says=["--operator-client", "empty command"], limit_s=20)
    check("scenario: -- with nothing after it", ["ocp_scenario", "run", str(ext), "--"], 2,
          says=["needs the client's command"], limit_s=20)
    check("scenario: --operator-client with --wait-for-clients", ["ocp_scenario", "run", str(ext), "--time", "real",
                                                                  "--wait-for-clients", "--operator-client", "true {port}"], 2,
          says=["--wait-for-clients is for clients started by hand"], limit_s=20)
    check("scenario: --realtime with --time virtual", ["ocp_scenario", "run", str(ext), "--realtime", "--time", "virtual"], 2,
          says=["contradict"], limit_s=20)
    check("campaign slurm: --max-events-per-s 5 is below its range",
          ["ocp_campaign", "slurm", "--print-only", "--max-events-per-s", "5"], 2, says=["--max-events-per-s"], limit_s=20)

    # vehicle_client without a port says which one it uses.
    check("vehicle_client: no port says it uses 4000",
          ["vehicle_client", "127.0.0.1", "--duration-s", "0.2", "--no-status"], 0, says=["no port in", "4000"], limit_s=20)

    subprocess.run(["rm", "-rf", str(scratch)])
    print(f"{len(failures)} failed" if failures else "every row passed")
    return 1 if failures else 0


def check_test_clients(commands):
    """The vtime tests' own clients (cli_errors.py BIN_DIR --test-clients PATH...): --help is exit 0
    with the usage, an unknown option exit 2 naming it; never a client that hangs or connects."""
    for command in commands:
        argv = [sys.executable, command] if command.endswith(".py") else [command]
        name = pathlib.Path(command).name
        check(f"{name} --help", argv + ["--help"], 0, says=["usage"], limit_s=20)
        check(f"{name} with an unknown option", argv + ["--no-such-option-here"], 2, says=["--no-such-option-here"], limit_s=20)
    print(f"{len(failures)} failed" if failures else "every row passed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(check_test_clients(sys.argv[3:]) if sys.argv[2:3] == ["--test-clients"] else main())
