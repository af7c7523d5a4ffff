#!/usr/bin/env python3
"""Checks the relative links of the repository's markdown pages: the README files, the user
guide (docs/guide/src) and the fuzzing notes. Every linked file must exist, and every anchor
(`page.md#heading`) must name a heading of its page. Links to the web are not fetched (no
network at test time). Prints each broken link and exits 1 if there is one."""

import re
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
PAGES = [
    REPO / "README.md",
    REPO / "topoccd" / "README.md",
    REPO / "topoccd-py" / "README.md",
    REPO / "fuzz" / "README.md",
    *sorted((REPO / "docs" / "guide" / "src").glob("*.md")),
]
LINK = re.compile(r"!?\[[^\]]*\]\(([^)\s]+)\)")


def prose(text: str) -> str:
    """The text outside fenced code blocks and inline code."""
    text = re.sub(r"^(`{3,}).*?^\1\s*$", "", text, flags=re.S | re.M)
    return re.sub(r"`+[^`\n]*`+", "", text)


def slug(heading: str) -> str:
    """The anchor of a heading, as GitHub and mdBook make it."""
    heading = re.sub(r"`", "", heading.strip().lower())
    heading = re.sub(r"[^\w\- ]", "", heading)
    return heading.replace(" ", "-")


def anchors(page: Path) -> set:
    return {slug(m.group(1)) for m in re.finditer(r"^#+\s+(.*)$", prose(page.read_text()), re.M)}


def main() -> int:
    broken = []
    checked = 0
    for page in PAGES:
        for target in LINK.findall(prose(page.read_text())):
            if re.match(r"^[a-z]+:", target):
                continue  # a web address
            path, _, anchor = target.partition("#")
            file = (page.parent / path).resolve() if path else page
            checked += 1
            if not file.exists():
                broken.append(f"{page.relative_to(REPO)}: {target}: no such file")
            elif anchor and file.suffix == ".md" and anchor not in anchors(file):
                broken.append(f"{page.relative_to(REPO)}: {target}: no heading #{anchor}")
    for line in broken:
        print(line)
    print(f"{checked} links checked in {len(PAGES)} pages, {len(broken)} broken")
    return 1 if broken else 0


if __name__ == "__main__":
    sys.exit(main())
