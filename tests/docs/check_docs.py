#!/usr/bin/env python3
"""Keeps docs/ from drifting away from the code (a CTest test, tests/CMakeLists.txt).

  check_docs.py config SOURCE_DIR TOOL=EXECUTABLE...
      Every key that `EXECUTABLE --help` lists must appear in docs/reference/TOOL-keys.md as a
      line  * `KEY` (SPEC)  with SPEC exactly the text in parentheses that --help prints after the
      key (type, and default / optional / required); and every such line must be a key of --help;
      docs/config.md must link to that page. And docs/reference/TOOL-keys.md must be exactly the
      output of `EXECUTABLE --help-markdown`, and docs/reference/effects.md of `identify-vehs
      --catalogue-markdown` (scripts/docs.sh --reference rewrites them).
  check_docs.py links SOURCE_DIR
      Relative links of README.md, docs/*.md, examples/ and data/**/README.md point to files that
      exist, and a link's #anchor into a Markdown page (or within the page) names one of that page's
      headings (GitHub's and MyST's slug: myst_heading_anchors in docs/site/conf.py); no file refers to contracts.md (its content is in docs/); every identifier that
      docs/library.md's "Using the library" table names is declared in include/vehs/; README.md
      is a guide of at most 250 lines (the studies live in docs/); and README.md, docs/**/*.md
      (but docs/reference/) and data/*/README.md are written for a reader, not as a lab notebook:
      no ISO date, day-month-year date, clock time with UTC, machine load ("load 5", "load ≈ 4"),
      "Round N" or "session" (the history scanner checks itself on known lines first).
  check_docs.py history SOURCE_DIR
      The history scan alone.
Exit status 0 when everything matches, else 1 with one line per problem.
"""
import os
import re
import subprocess
import sys

KEY_LINE = re.compile(r"^  (\S+)  \((.*)\)$")          # --help: "  key  (type, default x)"
DOC_LINE = re.compile(r"^\* `([^`]+)` \((.*)\)\s*$")   # docs:   "* `key` (type, default x)"


def help_keys(executable):
    out = subprocess.run([executable, "--help"], capture_output=True, text=True, timeout=60)
    if out.returncode != 0:
        raise SystemExit(f"{executable} --help exited with {out.returncode}: {out.stderr.strip()}")
    keys, inside = {}, False
    for line in out.stdout.splitlines():
        if line.startswith("Config keys"):
            inside = True
            continue
        if inside:
            if not line.strip():
                break
            m = KEY_LINE.match(line)
            if m:
                keys[m.group(1)] = m.group(2)
    if not keys:
        raise SystemExit(f"{executable} --help lists no config keys (format changed?)")
    return keys


def doc_sections(path):
    sections, current = {}, None
    with open(path, encoding="utf-8") as f:
        for number, line in enumerate(f, 1):
            line = line.rstrip("\n")
            if line.startswith("## "):
                current = line[3:].strip().strip("`")
                sections.setdefault(current, {})
            elif current is not None:
                m = DOC_LINE.match(line)
                if m:
                    sections[current][m.group(1)] = (m.group(2), number)
    return sections


def reference_keys(path):
    keys = {}
    with open(path, encoding="utf-8") as f:
        for number, line in enumerate(f, 1):
            m = DOC_LINE.match(line.rstrip("\n"))
            if m:
                keys[m.group(1)] = (m.group(2), number)
    return keys


def check_config(source, tools):
    with open(os.path.join(source, "docs", "config.md"), encoding="utf-8") as f:
        config_md = f.read()
    problems = []
    for spec in tools:
        tool, executable = spec.split("=", 1)
        keys = help_keys(executable)
        rel = f"docs/reference/{tool}-keys.md"
        path = os.path.join(source, rel)
        if f"(reference/{tool}-keys.md)" not in config_md:
            problems.append(f"docs/config.md: no link to reference/{tool}-keys.md")
        if not os.path.exists(path):
            problems.append(f"{rel} missing: run scripts/docs.sh --reference")
            continue
        with open(path, encoding="utf-8") as f:
            checked_in = f.read()
        generated = subprocess.run([executable, "--help-markdown"], capture_output=True, text=True,
                                   timeout=60).stdout
        if checked_in != generated:
            problems.append(f"{rel} differs from `{tool} --help-markdown`: run scripts/docs.sh --reference")
        documented = reference_keys(path)
        for key, text in keys.items():
            if key not in documented:
                problems.append(f"{rel} lacks key '{key}' of --help ({text})")
            elif documented[key][0] != text:
                problems.append(f"{rel}:{documented[key][1]}: {tool} '{key}' is documented as "
                                f"({documented[key][0]}) but --help says ({text})")
        for key, (_, number) in documented.items():
            if key not in keys:
                problems.append(f"{rel}:{number}: {tool} has no key '{key}' (not in --help)")
        if tool == "identify-vehs":  # the effect catalogue page, generated from the effect types
            rel = "docs/reference/effects.md"
            path = os.path.join(source, rel)
            generated = subprocess.run([executable, "--catalogue-markdown"], capture_output=True, text=True,
                                       timeout=60).stdout
            if not os.path.exists(path):
                problems.append(f"{rel} missing: run scripts/docs.sh --reference")
            else:
                with open(path, encoding="utf-8") as f:
                    if f.read() != generated:
                        problems.append(f"{rel} differs from `identify-vehs --catalogue-markdown`: "
                                        "run scripts/docs.sh --reference")
    return problems


README_MAX_LINES = 250
LINK = re.compile(r"\]\(([^)#\s]*)(#[^)\s]*)?\)")
FENCE = re.compile(r"^\s*(```|~~~)")
HEADING = re.compile(r"^(#{1,6})\s+(.*?)\s*#*\s*$")
SLUG_DROP = re.compile(r"[^\w\u4e00-\u9fff\- ]")


def heading_text(title):
    """A heading's text as rendered: links reduced to their text, code spans and emphasis unmarked."""
    title = re.sub(r"!?\[([^\]]*)\]\([^)]*\)", r"\1", title)
    return title.replace("`", "").replace("*", "")


def anchors(path):
    """The anchors of a Markdown page: GitHub-style slugs of its headings (duplicates get -1, -2, ...,
    as GitHub and MyST's github_slugify/unique_slug make them) and MyST targets "(name)=" ."""
    found, inside = set(), False
    with open(path, encoding="utf-8") as f:
        for line in f:
            if FENCE.match(line):
                inside = not inside
                continue
            if inside:
                continue
            target = re.match(r"^\((\S+)\)=\s*$", line)
            if target:
                found.add(target.group(1))
            m = HEADING.match(line)
            if m:
                slug = SLUG_DROP.sub("", heading_text(m.group(2)).lower().replace(" ", "-"))
                unique, i = slug, 1
                while unique in found:
                    unique, i = f"{slug}-{i}", i + 1
                found.add(unique)
    return found


def link_targets(text):
    """(target, anchor) of every Markdown link outside fenced code blocks."""
    inside, out = False, []
    for line in text.splitlines():
        if FENCE.match(line):
            inside = not inside
        elif not inside:
            out += [(m.group(1), (m.group(2) or "")[1:]) for m in LINK.finditer(line)]
    return out


def markdown_files(source):
    files = [os.path.join(source, "README.md")]
    for folder in ("docs", "examples", "data"):
        for root, dirs, names in os.walk(os.path.join(source, folder)):
            if folder == "docs" and "site" in dirs:
                dirs.remove("site")  # the site's own pages link within the built site (scripts/docs.sh)
            files += [os.path.join(root, n) for n in names if n.endswith(".md")]
    return files


def check_links(source):
    problems = []
    for path in markdown_files(source):
        with open(path, encoding="utf-8") as f:
            text = f.read()
        for target, anchor in link_targets(text):
            if re.match(r"^[a-z]+://", target) or target.startswith("mailto:"):
                continue
            full = os.path.normpath(os.path.join(os.path.dirname(path), target)) if target else path
            if not os.path.exists(full):
                problems.append(f"{os.path.relpath(path, source)}: link to missing '{target}'")
            elif anchor and full.endswith(".md") and anchor not in anchors(full):
                problems.append(f"{os.path.relpath(path, source)}: link to '{target}#{anchor}': "
                                f"{os.path.relpath(full, source)} has no heading with that anchor")
    for top in ("README.md", "docs", "include", "src", "apps", "data", "examples", "tests", "scripts", "bench"):
        full = os.path.join(source, top)
        walk = [(source, [], [top])] if os.path.isfile(full) else os.walk(full)
        for root, _, names in walk:
            for n in names:
                p = os.path.join(root, n)
                if os.path.realpath(p) == os.path.realpath(__file__) or not n.endswith((".md", ".hpp", ".cpp", ".sh", ".json", ".txt", ".py")):
                    continue
                with open(p, encoding="utf-8", errors="replace") as f:
                    for number, line in enumerate(f, 1):
                        if "contracts.md" in line:
                            problems.append(f"{os.path.relpath(p, source)}:{number}: refers to contracts.md "
                                            "(now docs/: see docs/README.md)")
    problems += check_readme_names(source)
    with open(os.path.join(source, "README.md"), encoding="utf-8") as f:
        lines = f.read().count("\n")
    if lines > README_MAX_LINES:
        problems.append(f"README.md: {lines} lines, at most {README_MAX_LINES} (move detail to docs/)")
    return problems


def check_readme_names(source):
    """Identifiers in the third column of docs/library.md's "Using the library" table exist in include/."""
    with open(os.path.join(source, "docs", "library.md"), encoding="utf-8") as f:
        readme = f.read()
    start = readme.find("## Using the library")
    if start < 0:
        return ["docs/library.md: no section '## Using the library'"]
    section = readme[start:readme.find("\n## ", start + 1)]
    headers = ""
    for root, _, names in os.walk(os.path.join(source, "include", "vehs")):
        for n in names:
            with open(os.path.join(root, n), encoding="utf-8") as f:
                headers += f.read()
    problems = []
    for row in section.splitlines():
        cells = row.split("|")
        if len(cells) < 4 or cells[1].strip() in ("area (target)", "---"):
            continue
        for name in re.findall(r"`([A-Za-z_][A-Za-z0-9_:]*)`", cells[3]):
            short = name.split("::")[-1]
            if not re.search(r"\b" + re.escape(short) + r"\b", headers):
                problems.append(f"docs/library.md: 'Using the library' names '{name}', which include/vehs/ does not declare")
    return problems


HISTORY = [
    (re.compile(r"\b20\d\d-\d\d-\d\d\b"), "an ISO date"),
    (re.compile(r"\b\d{1,2} (?:Jan|Feb|Mar|Apr|May|Jun|Jul|Aug|Sep|Oct|Nov|Dec)[a-z]*\.? 20\d\d\b"), "a date"),
    (re.compile(r"\b\d{1,2}:\d\d\s*(?:[–-]\s*(?:\d{1,2}:\d\d\s*)?)?UTC\b"), "a clock time (UTC)"),
    (re.compile(r"\bloads?\s*(?:[≈~]|\d)", re.IGNORECASE), "a machine load"),
    (re.compile(r"\bround\s+\d+\b", re.IGNORECASE), "a numbered round"),
    (re.compile(r"\bsessions?\b", re.IGNORECASE), "a session"),
]
HISTORY_BAD = ["Measured 2026-11-21 with OpenBLAS", "Round 8 (24 Nov 19:10-21:01 UTC, nice 19",
               "**Round 14 (25 Nov 12:00– UTC):", "10.7 s under load 5 on 2 cores", "(load ≈ 4; full output",
               "load ~ 4", "stopped at the session's end", "checked on 24 Nov 2026 with fits from the truth"]
HISTORY_GOOD = ["10⁶ samples in 5.41 s wall on 2 threads", "the records are loaded once (load time 0.13 s)",
                "repeated (at most 3 rounds)", "round-off of 1e-16", "Python session objects are not kept",
                "x0 uniform in [−1.5, 1.5], Δt = 0.001", "at 12:00 on the clock", "2 cores, 10 s"]


def history_hits(line):
    """What in a line reads as lab-notebook history: [(kind, matched text)]."""
    hits = [(kind, m.group(0)) for pattern, kind in HISTORY for m in [pattern.search(line)] if m]
    if re.search(r"\bsessions?\b", line, re.IGNORECASE) and re.search(r"\bPython session", line):
        hits = [h for h in hits if h[0] != "a session"]  # an interpreter's session is not history
    return hits


def history_self_test():
    """The scanner must flag every known bad line and pass every known good one."""
    problems = [f"check_docs.py: the history scanner misses {line!r}" for line in HISTORY_BAD if not history_hits(line)]
    problems += [f"check_docs.py: the history scanner flags {line!r} ({history_hits(line)})"
                 for line in HISTORY_GOOD if history_hits(line)]
    return problems


def history_files(source):
    files = [os.path.join(source, "README.md")]
    for root, dirs, names in os.walk(os.path.join(source, "docs")):
        if os.path.relpath(root, source) == "docs" and "reference" in dirs:
            dirs.remove("reference")  # generated from the tools' --help
        files += [os.path.join(root, n) for n in names if n.endswith(".md")]
    data = os.path.join(source, "data")
    files += [os.path.join(data, d, "README.md") for d in sorted(os.listdir(data))
              if os.path.isfile(os.path.join(data, d, "README.md"))]
    return sorted(files)


def check_history(source):
    """Docs are written for a reader: no dates, clock times, machine loads, rounds or sessions."""
    problems = history_self_test()
    for path in history_files(source):
        with open(path, encoding="utf-8") as f:
            for number, line in enumerate(f, 1):
                for kind, text in history_hits(line):
                    problems.append(f"{os.path.relpath(path, source)}:{number}: {kind} ('{text}'): "
                                    "docs describe what is, without dates, loads or session history")
    return problems


def main(argv):
    if len(argv) >= 3 and argv[1] == "config":
        problems = check_config(argv[2], argv[3:])
    elif len(argv) == 3 and argv[1] == "links":
        problems = check_links(argv[2]) + check_history(argv[2])
    elif len(argv) == 3 and argv[1] == "history":
        problems = check_history(argv[2])
    else:
        print(__doc__)
        return 2
    for p in problems:
        print(p)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
