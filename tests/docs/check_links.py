#!/usr/bin/env python3
"""Every relative link and #anchor in the project's Markdown resolves, offline.

Checks README.md, docs/ and the other READMEs: a link to a file or folder must name one that
exists (relative to the page), and a #fragment must name a heading of its target page, as GitHub
makes anchors of headings (lowercase; punctuation other than '-' and '_' dropped; spaces to '-';
a repeated heading gets -1, -2, ...) or an explicit <a id="...">. Links with a scheme (https:,
mailto:) are not fetched: the suite runs without a network. docs/README.md, the index, must link
every other page under docs/. Code spans and fenced blocks are
skipped. Exit code 1 and one line per broken link.

usage: check_links.py REPO_ROOT
"""
import re
import sys
from pathlib import Path

PAGES = ["README.md", "docs/**/*.md", "bench/README.md", "docker/README.md",
         "tests/fuzz/README.md"]
LINK = re.compile(r"!?\[(?:[^\]\\]|\\.)*\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)")
FENCE = re.compile(r"^\s*(```|~~~)")
CODE_SPAN = re.compile(r"(`+).*?\1")
ANCHOR_TAG = re.compile(r"<a\s+(?:name|id)=\"([^\"]+)\"")


def prose_lines(text):
    """The page's lines outside fenced blocks, with code spans blanked."""
    inside = False
    for number, line in enumerate(text.splitlines(), 1):
        if FENCE.match(line):
            inside = not inside
            continue
        if not inside:
            yield number, CODE_SPAN.sub("", line)


def slug(heading):
    text = re.sub(r"<[^>]+>", "", heading).strip().lower()
    text = re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", text)  # a link in a heading keeps its text
    text = text.replace("`", "")
    text = "".join(c for c in text if c.isalnum() or c in " -_")
    return text.replace(" ", "-")


def anchors(page, cache={}):
    if page not in cache:
        found, seen = set(), {}
        text = page.read_text(encoding="utf-8")
        inside = False
        for line in text.splitlines():
            if FENCE.match(line):
                inside = not inside
                continue
            if inside:
                continue
            found.update(ANCHOR_TAG.findall(line))
            m = re.match(r"^#{1,6}\s+(.*?)\s*#*\s*$", line)
            if m:
                base = slug(m.group(1))
                n = seen.get(base, 0)
                seen[base] = n + 1
                found.add(base if n == 0 else f"{base}-{n}")
        cache[page] = found
    return cache[page]


def broken_links(root, counts):
    pages = sorted({p for pattern in PAGES for p in root.glob(pattern) if p.is_file()})
    counts["pages"] = len(pages)
    for page in pages:
        for number, line in prose_lines(page.read_text(encoding="utf-8")):
            for target in LINK.findall(line):
                if re.match(r"^[a-z][a-z0-9+.-]*:", target, re.I):
                    continue  # https:, mailto: ... not fetched
                counts["links"] += 1
                path, _, fragment = target.partition("#")
                dest = (page.parent / path).resolve() if path else page
                where = f"{page.relative_to(root)}:{number}: {target}"
                if not dest.exists():
                    yield f"{where}: no such file"
                elif fragment and dest.suffix == ".md" and fragment not in anchors(dest):
                    yield f"{where}: no heading or anchor #{fragment} in {dest.relative_to(root)}"


def unindexed_pages(root):
    """The pages under docs/ that docs/README.md does not link."""
    index = root / "docs" / "README.md"
    linked = set()
    for _, line in prose_lines(index.read_text(encoding="utf-8")):
        for target in LINK.findall(line):
            path = target.partition("#")[0]
            if path and not re.match(r"^[a-z][a-z0-9+.-]*:", path, re.I):
                linked.add((index.parent / path).resolve())
    for page in sorted((root / "docs").glob("**/*.md")):
        if page != index and page.resolve() not in linked:
            yield f"docs/README.md: does not link {page.relative_to(root)}"


def main():
    root = Path(sys.argv[1] if len(sys.argv) > 1 else ".").resolve()
    counts = {"pages": 0, "links": 0}
    broken = list(broken_links(root, counts)) + list(unindexed_pages(root))
    for line in broken:
        print(line)
    print(f"check_links: {counts['links']} relative links in {counts['pages']} pages, "
          f"{len(broken)} broken")
    sys.exit(1 if broken else 0)


if __name__ == "__main__":
    main()
