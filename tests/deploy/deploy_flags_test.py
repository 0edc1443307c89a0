#!/usr/bin/python3
"""Keeps the deployment files in step with the binaries (issue: secure links, item 5): every
flag that the Kubernetes manifests (deploy/k8s), the systemd units (deploy/systemd) and the
container's entrypoint (deploy/container) pass must be one of that binary's flags in its
--help, options that take a value must get one and flags must not. The checker is first shown
a manifest with a wrong flag, a missing value and a value given to a flag, and must report
each (it can fail). Usage: deploy_flags_test.py SOURCE_DIR BUILD_DIR"""
import glob
import os
import re
import subprocess
import sys

import yaml

BINARIES = {"pathfarm-coordinator": "coordinator", "pathfarm-tracer": "tracer-node",
            "pathfarm-client": "client", "pathfarm-render": "tools"}


def help_flags(build, name):
    """{flag: takes_value} from the binary's --help (CLI11: '  --width INT [640] ...')."""
    text = subprocess.run([os.path.join(build, BINARIES[name], name), "--help"], capture_output=True,
                          text=True, check=True).stdout
    flags = {}
    for line in text.splitlines():
        # The value's type follows the flag after one space (INT=0, TEXT REQUIRED, FLOAT:...);
        # the description after the column's padding.
        m = re.match(r"\s+(?:-\w,)?(--[\w-]+)( [A-Z][A-Z0-9_]*(?:[=:]\S*)?)?(?:\s|$)", line)
        if m:
            flags[m.group(1)] = m.group(2) is not None
    if "--help" not in flags:
        raise SystemExit(f"deploy_flags: {name} --help lists no flags:\n{text[:500]}")
    return flags


def check_args(where, name, args, flags):
    """Problems with one command line (a list of arguments) of binary `name`."""
    problems = []
    i = 0
    while i < len(args):
        a = str(args[i])
        if a.startswith("--"):
            flag = a.split("=", 1)[0]
            if flag not in flags:
                problems.append(f"{where}: {name} has no flag {flag}")
            elif flags[flag] and "=" not in a:
                if i + 1 >= len(args) or str(args[i + 1]).startswith("--"):
                    problems.append(f"{where}: {name} {flag} needs a value")
                else:
                    i += 1  # skip the value
            elif not flags[flag] and i + 1 < len(args) and not str(args[i + 1]).startswith("-"):
                problems.append(f"{where}: {name} {flag} takes no value, given {args[i + 1]}")
        i += 1
    return problems


def manifest_commands(path):
    """(where, binary, args) of every container in the YAML documents at path."""
    out = []
    for doc in yaml.safe_load_all(open(path)):
        spec = ((doc or {}).get("spec") or {}).get("template", {}).get("spec", {})
        for c in spec.get("containers", []):
            name = os.path.basename((c.get("command") or [""])[0])
            out.append((f"{path}: container {c.get('name')}", name, c.get("args") or []))
    return out


def unit_commands(path):
    """(where, binary, args) of a systemd unit: ExecStart, and the arguments its comments give
    as examples of the environment file's *_ARGS."""
    text = open(path).read()
    m = re.search(r"^ExecStart=(\S+)\s+(.*)$", text, re.M)
    name = os.path.basename(m.group(1))
    out = [(f"{path}: ExecStart", name, m.group(2).split())]  # ${VAR} counts as a value
    for line in text.splitlines():  # "# ... PATHFARM_ARGS=--width 1280 ..." and "(e.g. --threads 16)"
        if line.startswith("#") and "ARGS" in line and "--" in line:
            documented = line[line.index("--"):].split(")")[0]
            out.append((f"{path}: comment '{documented}'", name, documented.split()))
    return out


def dockerfile_commands(path):
    m = re.search(r'^ENTRYPOINT\s+(\[.*\])', open(path).read(), re.M)
    cmd = yaml.safe_load(m.group(1))
    return [(f"{path}: ENTRYPOINT", os.path.basename(cmd[0]), cmd[1:])]


def self_check(build):
    """The checker must catch a wrong flag, a missing value and a value given to a flag."""
    flags = help_flags(build, "pathfarm-tracer")
    bad = check_args("self-check", "pathfarm-tracer",
                     ["--no-such-flag", "--threads", "--insecure-plaintext", "yes"], flags)
    wanted = ["has no flag --no-such-flag", "--threads needs a value", "--insecure-plaintext takes no value"]
    for w in wanted:
        if not any(w in b for b in bad):
            raise SystemExit(f"deploy_flags: the checker missed '{w}': {bad}")


def main():
    source, build = sys.argv[1], sys.argv[2]
    self_check(build)
    commands = []
    for path in sorted(glob.glob(os.path.join(source, "deploy", "k8s", "*.yaml"))):
        commands += manifest_commands(path)
    for path in sorted(glob.glob(os.path.join(source, "deploy", "systemd", "*.service"))):
        commands += unit_commands(path)
    commands += dockerfile_commands(os.path.join(source, "deploy", "container", "Dockerfile"))
    binaries = {name for _, name, _ in commands}
    if not {"pathfarm-coordinator", "pathfarm-tracer"} <= binaries:
        raise SystemExit(f"deploy_flags: expected coordinator and tracer commands, found {binaries}")
    cache, problems = {}, []
    for where, name, args in commands:
        if name not in BINARIES:
            problems.append(f"{where}: unknown binary {name}")
            continue
        cache.setdefault(name, help_flags(build, name))
        problems += check_args(where, name, args, cache[name])
    for p in problems:
        print(p)
    print(f"deploy_flags: {len(commands)} command lines checked, {len(problems)} problem(s)")
    sys.exit(1 if problems else 0)


if __name__ == "__main__":
    main()
