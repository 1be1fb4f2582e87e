#!/usr/bin/env python3
"""Where the code stands against issue 60's targets: lines of Rust per crate (target: none over
10k), `FrameParams`' fields (target: at most 18, none naming one technique) and, for each of its
fields and its `FrameOptions`' of a name of more than one word, how many source files outside the
tests name it, and the same for the render options themselves (`FrameOptions`' fields and the
path loop's knobs, `PathLoop`'s): what adding an option like it touches (target: 4: the table,
its logic, its shader, its test), and the files that list most options of a kind by hand (what
a new one must join besides). Prints one line per measure and a JSON
summary last; exits 1 only when a ceiling given with --ceilings is passed (the structure test's
ratchet: what was reached stays reached).
Usage: tools/code_targets.py [--ceilings FILE] [repo-root]"""
import json, os, re, sys

def rust_files(folder):
    for root, _, files in os.walk(folder):
        for f in files:
            if f.endswith(".rs"):
                yield os.path.join(root, f)

def lines(path):
    with open(path, encoding="utf-8") as f:
        return sum(1 for _ in f)

def crate_lines(root):
    out = {}
    crates = os.path.join(root, "crates")
    for name in sorted(os.listdir(crates)):
        src = os.path.join(crates, name, "src")
        if os.path.isdir(src):
            out[name] = sum(lines(p) for p in rust_files(src))
    return out

def struct_fields(root, file, name):
    text = open(os.path.join(root, file), encoding="utf-8").read()
    body = text[text.index(f"pub struct {name} {{"):]
    body = body[: body.index("\n}\n")]
    return re.findall(r"^\s*pub (\w+):", body, re.M)

def frame_params_fields(root):
    return struct_fields(root, "crates/platoon-frame/src/frame/mod.rs", "FrameParams")

def frame_options_fields(root):
    """The options a request passes to the frame as they are (`FrameParams::options`)."""
    return struct_fields(root, "crates/platoon-frame/src/frame/options.rs", "FrameOptions")

def path_loop_fields(root):
    """The path loop's knobs (`FrameParams::path_loop`), each a render option."""
    return struct_fields(root, "crates/platoon-frame/src/frame/path_loop.rs", "PathLoop")

def source_files(root):
    """Non-test sources: the crates' src folders (their `tests.rs` files and `mod tests`
    blocks aside, roughly: a file whose name says test), the shaders and the Python stub."""
    for base in ("crates", "shaders"):
        for dirpath, _, files in os.walk(os.path.join(root, base)):
            if "/tests" in dirpath or "/examples" in dirpath or "/target" in dirpath:
                continue
            for f in files:
                if f.endswith((".rs", ".glsl", ".comp", ".pyi")) and "test" not in f:
                    yield os.path.join(dirpath, f)

def naming_files(root, fields):
    texts = {}
    for p in source_files(root):
        text = open(p, encoding="utf-8").read()
        # The tests' block of a file is not where an option is declared or used.
        texts[p] = text.split("#[cfg(test)]\nmod tests")[0]
    out = {}
    for field in fields:
        pattern = re.compile(r"\b" + field + r"\b")
        out[field] = sum(1 for t in texts.values() if pattern.search(t))
    return out

def enumerating_files(root, fields):
    """Source files that name more than half of `fields`, and at least three (a file that
    treats two options apart is no list): the hand-kept lists a new option of their kind must
    join (the declaration, its table, a mirror such as a GLSL block), lines made from a table
    aside."""
    patterns = [re.compile(r"\b" + f + r"\b") for f in fields]
    out = []
    for p in source_files(root):
        text = open(p, encoding="utf-8").read().split("#[cfg(test)]\nmod tests")[0]
        # Lines a test writes from a table (`<made from ...>` to `</made from ...>`, e.g. the
        # Python stub's keywords of the request's table) are not kept by hand.
        text = MADE.sub("", text)
        named = sum(1 for pat in patterns if pat.search(text))
        if 2 * named > len(fields) and named >= 3:
            out.append(os.path.relpath(p, root))
    return sorted(out)

MADE = re.compile(r"<made from [^>]*>.*?</made from [^>]*>", re.S)

def main(argv):
    ceilings = None
    if len(argv) > 1 and argv[1] == "--ceilings":
        ceilings = json.load(open(argv[2]))
        argv = argv[:1] + argv[3:]
    root = argv[1] if len(argv) > 1 else os.path.join(os.path.dirname(__file__), "..")
    crates = crate_lines(root)
    for name, n in sorted(crates.items(), key=lambda kv: -kv[1]):
        print(f"crate {name}: {n} lines{'  (over 10k)' if n > 10000 else ''}")
    fields = frame_params_fields(root)
    print(f"FrameParams: {len(fields)} fields (target 18)")
    # Names of more than one word: a common word (frame, width, film) is named everywhere for
    # other reasons, so only these say what an option touches.
    options = frame_options_fields(root)
    print(f"FrameOptions (FrameParams::options): {len(options)} fields")
    knobs = path_loop_fields(root)
    # The sources read once for every name either measure counts.
    named = naming_files(root, sorted({f for f in fields + options + knobs if "_" in f}))
    files = {f: named[f] for f in fields + options if "_" in f}
    for field, n in sorted(files.items(), key=lambda kv: -kv[1]):
        print(f"  {field}: named in {n} source files (target 4)")
    # The render options themselves (what the target's "a new render option" is): the frame
    # options a request gives as they are and the path loop's knobs. An option other code must
    # treat apart (a time limit refused where frames cannot be cut) is named where it is.
    print(f"render options (FrameOptions and PathLoop): {len(options) + len(knobs)}")
    option_files = {f: named[f] for f in options + knobs if "_" in f}
    for field, n in sorted(option_files.items(), key=lambda kv: -kv[1]):
        print(f"  {field}: named in {n} source files (target 4)")
    # The hand-kept lists of each kind of option: what adding one touches beyond its logic,
    # its shader and its test.
    enumerating = {}
    for kind, group in (("frame options", options), ("path loop knobs", knobs)):
        listed = enumerating_files(root, [f for f in group if "_" in f])
        enumerating[kind] = len(listed)
        print(f"files listing most {kind} by hand: {len(listed)}: {', '.join(listed)}")
    summary = {
        "largest_crate_lines": max(crates.values()),
        "crates_over_10k": sorted(n for n, l in crates.items() if l > 10000),
        "frame_params_fields": len(fields),
        "most_files_naming_a_frame_option": max(files.values()),
        "most_files_naming_a_render_option": max(option_files.values()),
        "render_options_within_4_files": sum(1 for n in option_files.values() if n <= 4),
        "most_files_listing_one_kind_of_option": max(enumerating.values()),
    }
    print(json.dumps(summary))
    if ceilings is not None:
        passed = []
        for key in ("largest_crate_lines", "frame_params_fields", "most_files_naming_a_frame_option",
                    "most_files_naming_a_render_option", "most_files_listing_one_kind_of_option"):
            if summary[key] > ceilings[key]:
                passed.append(f"{key} {summary[key]} over its ceiling {ceilings[key]}")
        extra = set(summary["crates_over_10k"]) - set(ceilings["crates_over_10k"])
        if extra:
            passed.append(f"crates newly over 10k lines: {sorted(extra)}")
        for p in passed:
            print("over:", p)
        return 1 if passed else 0
    return 0

if __name__ == "__main__":
    sys.exit(main(sys.argv))
