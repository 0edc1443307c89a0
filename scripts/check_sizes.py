#!/usr/bin/env python3
"""Size check (STYLE.md §4): no non-test source file over 400 lines, and no function over 60
lines outside OpenCL kernels (.cl) and lookup tables (a function marked with the comment
"check_sizes: lookup table" on or above its first line). Prints one line per violation and exits
1 if any. Functions are found by a light parser: a brace that opens after a parenthesised
parameter list at namespace or class level (not a control statement, lambda or initialiser)
starts a function, which ends at its matching brace; lambdas count towards the function that
holds them. `--self-test` checks the parser on known snippets."""
import os
import re
import sys

MAX_FILE_LINES = 400
MAX_FUNCTION_LINES = 60
SOURCE_DIRS = ["common", "coordinator", "tracer-node", "client", "tools", "bench"]
EXTENSIONS = (".h", ".cpp", ".cl", ".clh")
TABLE_MARK = "check_sizes: lookup table"  # a comment on or above a function that is data
CONTROL = re.compile(r"^\s*(if|for|while|switch|catch|do|else|return|case)\b")
NOT_FUNCTION = re.compile(r"\b(namespace|class|struct|enum|union)\b[^()]*$")


def strip(line):
    """The line without comments and string or character literals (their braces do not count)."""
    line = re.sub(r'"(\\.|[^"\\])*"', '""', line)
    line = re.sub(r"'(\\.|[^'\\])*'", "''", line)
    return line.split("//", 1)[0]


def functions(lines):
    """(name, first line, line count) of every function body in the file."""
    found = []
    depth = 0
    head = ""  # text since the last ; { or } at the current depth (a possible signature)
    start = None  # (depth at which the function's body opened, its first line, its name)
    in_block_comment = False
    for number, raw in enumerate(lines, 1):
        line = raw
        if in_block_comment:
            if "*/" not in line:
                continue
            line = line.split("*/", 1)[1]
            in_block_comment = False
        if "/*" in line and "*/" not in line.split("/*", 1)[1]:
            line = line.split("/*", 1)[0]
            in_block_comment = True
        line = strip(line)
        if line.lstrip().startswith("#"):
            continue
        for ch in line:
            if ch == "{":
                if start is None and is_signature(head):
                    start = (depth, number, name_of(head))
                depth += 1
                head = ""
            elif ch == "}":
                depth -= 1
                if start is not None and depth == start[0]:
                    found.append((start[2], start[1], number - start[1] + 1))
                    start = None
                head = ""
            elif ch == ";":
                head = ""
            else:
                head += ch
        head += " "
    return found


def is_signature(head):
    text = " ".join(head.split())
    if not text or ")" not in text or CONTROL.match(text) or NOT_FUNCTION.search(text):
        return False
    if text.rstrip().endswith("=") or "](" in text.replace(" ", "") and "operator" not in text:
        return False  # an initialiser or a lambda
    tail = text[text.rindex(")") + 1:]  # after the parameter list: qualifiers only
    return re.fullmatch(r"\s*((const|override|final|noexcept|mutable|->\s*[\w:<>,\s*&]+)\s*)*"
                        r"(:\s*.*)?", tail) is not None


def name_of(head):
    text = " ".join(head.split())
    m = re.search(r"([\w:~]+|operator\S*)\s*\(", text)
    return m.group(1) if m else text[:40]


def check(root):
    problems = []
    for d in SOURCE_DIRS:
        for dirpath, _, names in os.walk(os.path.join(root, d)):
            for n in sorted(names):
                if not n.endswith(EXTENSIONS):
                    continue
                path = os.path.join(dirpath, n)
                rel = os.path.relpath(path, root)
                with open(path, encoding="utf-8") as f:
                    lines = f.read().splitlines()
                if len(lines) > MAX_FILE_LINES:
                    problems.append(f"{rel}: {len(lines)} lines (at most {MAX_FILE_LINES})")
                if n.endswith((".cl", ".clh")):
                    continue
                for name, first, count in functions(lines):
                    marked = any(TABLE_MARK in lines[k] for k in (first - 2, first - 1) if k >= 0)
                    if count > MAX_FUNCTION_LINES and not marked:
                        problems.append(f"{rel}:{first}: function {name} is {count} lines "
                                        f"(at most {MAX_FUNCTION_LINES})")
    return problems


def self_test():
    snippet = """
namespace a {
int short_one(int x) { return x; }
struct S {
    void method() const {
        if (true) {
            auto l = [&](int y) {
                return y;
            };
        }
    }
    int table[3] = {1, 2, 3};
};
Result<int> Widget::long_one(const std::string& s)
    const {
""" + "    x();\n" * 70 + """}
}  // namespace a
"""
    found = {name: count for name, _, count in functions(snippet.splitlines())}
    expected_long = 72
    ok = found.get("short_one") == 1 and found.get("method") == 7 and \
        found.get("Widget::long_one") == expected_long and len(found) == 3
    print("check_sizes self-test:", "ok" if ok else f"FAILED {found}")
    return 0 if ok else 1


def main():
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    if "--self-test" in sys.argv:
        return self_test()
    problems = check(root)
    for p in problems:
        print(p)
    print(f"check_sizes: {len(problems)} problem(s)")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
