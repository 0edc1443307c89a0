#!/usr/bin/env python3
"""Layering check (STYLE.md §2): every #include "..." written from the repository root must
respect the module dependency table, and heavy third-party headers may appear only in the
folders that own them. Prints one line per violation and exits 1 if any."""
import os
import re
import sys

# module prefix -> module prefixes it may include (besides itself)
ALLOWED = {
    "common/base": [],
    "common/math": ["common/base"],
    "common/sampling": ["common/base", "common/math"],
    "common/film": ["common/base", "common/math"],
    "common/scene": ["common/base", "common/math"],
    "common/scene/load": ["common/base", "common/math", "common/scene", "common/film"],
    "common/commit": ["common/base", "common/math", "common/scene", "proto"],
    "common/render": ["common/base", "common/math", "common/sampling", "common/scene", "common/film"],
    "common/net": ["common/base", "proto"],
    "common/wire": ["common/base", "common/math", "common/scene", "common/commit", "common/net",
                    "proto"],
    "common/cli": ["common/base"],
    "coordinator/balance": ["common/base"],
    "coordinator": ["common", "proto"],
    "tracer-node": ["common", "proto"],
    "client": ["common", "proto"],
    "tools": ["common", "coordinator", "tracer-node", "client", "tools", "proto"],
    "tests": ["common", "coordinator", "tracer-node", "client", "tools", "tests", "proto"],
    "bench": ["common", "coordinator", "tracer-node", "client", "tools", "bench", "tests", "proto"],
}

# third-party header prefix -> folders (or files) allowed to include it
RESTRICTED = {
    "embree3/": ["tracer-node/embree/", "coordinator/accel/", "bench/"],
    "CL/": ["tracer-node/opencl/", "bench/"],
    "OpenImageIO/": ["common/film/oiio_module.cpp"],
    "asio": ["common/net/", "coordinator/session/", "tracer-node/", "client/", "tests/", "bench/"],
    "SDL": ["client/", "tests/"],
    "turbojpeg.h": ["common/film/jpeg_codec.cpp",
                    "tests/unit/common/film/jpeg_texture_test.cpp"],  # encodes its test inputs
    "websocketpp/": ["coordinator/http/web_server.cpp"],
    "libavcodec/": ["common/film/h264_codec.cpp"],
    "libswscale/": ["common/film/h264_codec.cpp"],
    "libavutil/": ["common/film/h264_codec.cpp"],
    "openssl/": ["common/net/auth.cpp", "common/net/tls_psk.cpp", "coordinator/http/",
                 "tests/support/raw_peer.cpp"],
}

# quoted project headers that only some files may include
RESTRICTED_LOCAL = {
    # The commit codec's protobuf side: only the codec's own .cpp files and common/wire's.
    "common/commit/codec_internal.h": ["common/commit/op_codec.cpp", "common/commit/field_codec.cpp",
                                       "common/commit/commit_codec.cpp", "common/wire/messages.cpp"],
}
# files in common that may include protobuf headers (*.pb.h)
PROTOBUF_IN_COMMON = ("common/commit/commit_codec.cpp", "common/commit/op_codec.cpp",
                      "common/commit/field_codec.cpp", "common/commit/codec_internal.h",
                      "common/net/", "common/wire/")

INCLUDE = re.compile(r'^\s*#\s*include\s*([<"])([^>"]+)[>"]')
SOURCE_DIRS = ["common", "coordinator", "tracer-node", "client", "tools", "tests", "bench"]


def module_of(path):
    """Longest ALLOWED key that prefixes path."""
    best = None
    for key in ALLOWED:
        if path.startswith(key + "/") and (best is None or len(key) > len(best)):
            best = key
    return best


def target_module(include):
    parts = include.split("/")
    for depth in (3, 2, 1):
        candidate = "/".join(parts[:depth])
        if candidate in ALLOWED or candidate in ("common", "proto"):
            return candidate
    return parts[0]


def allowed(src_module, inc):
    if inc.startswith(src_module + "/") or inc.startswith("pathfarm/"):
        return inc.startswith(src_module + "/") or "proto" in ALLOWED[src_module]
    return any(inc.startswith(dep + "/") for dep in ALLOWED[src_module])


def check(root):
    errors = []
    for top in SOURCE_DIRS:
        for dirpath, _, files in os.walk(os.path.join(root, top)):
            for name in files:
                if not name.endswith((".h", ".cpp", ".cl", ".clh")):
                    continue
                full = os.path.join(dirpath, name)
                rel = os.path.relpath(full, root)
                module = module_of(rel)
                with open(full, encoding="utf-8", errors="replace") as f:
                    for lineno, line in enumerate(f, 1):
                        m = INCLUDE.match(line)
                        if not m:
                            continue
                        kind, inc = m.groups()
                        if kind == "<":
                            for prefix, owners in RESTRICTED.items():
                                if inc.startswith(prefix) and not any(rel.startswith(o) for o in owners):
                                    errors.append(f"{rel}:{lineno}: <{inc}> may only be included from {', '.join(owners)}")
                            continue
                        if inc in RESTRICTED_LOCAL and rel not in RESTRICTED_LOCAL[inc]:
                            errors.append(f"{rel}:{lineno}: \"{inc}\" may only be included from "
                                          f"{', '.join(RESTRICTED_LOCAL[inc])}")
                            continue
                        if inc.endswith(".pb.h") and rel.startswith("common/") and not rel.startswith(
                                PROTOBUF_IN_COMMON):
                            errors.append(f"{rel}:{lineno}: \"{inc}\": in common only the commit codec, net/ "
                                          "and wire/ see protobuf")
                            continue
                        if "/" not in inc:
                            errors.append(f"{rel}:{lineno}: \"{inc}\": write includes from the repository root")
                            continue
                        if module and not allowed(module, inc):
                            errors.append(f"{rel}:{lineno}: {module} may not include \"{inc}\" (STYLE.md §2)")
    return errors


def self_test():
    """The check must catch an upward include and a misplaced heavy header."""
    import tempfile
    with tempfile.TemporaryDirectory() as tmp:
        os.makedirs(os.path.join(tmp, "common/base"))
        with open(os.path.join(tmp, "common/base/bad.h"), "w") as f:
            f.write('#include "coordinator/balance/balancer.h"\n#include <embree3/rtcore.h>\n#include "common/base/check.h"\n')
        errors = check(tmp)
    ok = len(errors) == 2
    print(f"layering self-test: {'ok' if ok else 'FAILED'} ({len(errors)} violations found, 2 expected)")
    return 0 if ok else 1


def main():
    if len(sys.argv) > 1 and sys.argv[1] == "--self-test":
        return self_test()
    root = sys.argv[1] if len(sys.argv) > 1 else "."
    errors = check(root)
    for e in errors:
        print(e)
    print(f"layering: {len(errors)} violation(s)")
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main())
