#!/usr/bin/env python3
"""Check the links of the built book and of README.md (Python 3 standard library only).

    python3 scripts/check_book_links.py [BOOK_DIR] [--repo ROOT]

BOOK_DIR is the book built by `mdbook build docs` (default: out/book under the repository root).
Every relative `href` and `src` of every built HTML page must name a file of the built book;
a `#anchor` must be the id (or the name of an <a>) of an element of the target page. Every
relative link and image of README.md (and scenes/README.md) must name a file of the repository, and a `#anchor` in it
a heading of the target Markdown file. External links (http, https, mailto, …) are only counted:
nothing is fetched. Prints every broken link with its page and exits 1 if there is one.
"""

import argparse
import html.parser
import os
import re
import sys
import urllib.parse

EXTERNAL = re.compile(r"^(?:[a-zA-Z][a-zA-Z0-9+.-]*:|//)")


class Page(html.parser.HTMLParser):
    """The ids, the <base href> and the links (tag, attribute, value) of one HTML page."""

    def __init__(self):
        super().__init__(convert_charrefs=True)
        self.ids = set()
        self.links = []
        self.base = None

    def handle_starttag(self, tag, attrs):
        for name, value in attrs:
            if value is None:
                continue
            if name == "id" or (tag == "a" and name == "name"):
                self.ids.add(value)
            elif tag == "base" and name == "href":
                self.base = value
            elif name in ("href", "src"):
                self.links.append((tag, name, value))

    handle_startendtag = handle_starttag


def parse_html(path, cache):
    if path not in cache:
        page = Page()
        with open(path, encoding="utf-8", errors="replace") as f:
            page.feed(f.read())
        cache[path] = page
    return cache[path]


def check_book(book, broken, counts):
    cache = {}
    book = os.path.realpath(book)
    for root, _dirs, files in os.walk(book):
        for name in sorted(files):
            if not name.endswith(".html"):
                continue
            page_path = os.path.join(root, name)
            page = parse_html(page_path, cache)
            rel_page = os.path.relpath(page_path, book)
            # A <base href> changes what relative links are relative to (mdBook's 404 page).
            base_dir = os.path.dirname(page_path)
            if page.base is not None and not EXTERNAL.match(page.base):
                if page.base.startswith("/"):
                    base_dir = os.path.join(book, page.base.lstrip("/"))
                else:
                    base_dir = os.path.join(base_dir, page.base)
            seen = set()
            for tag, attr, value in page.links:
                value = value.strip()
                if (tag, attr, value) in seen:
                    continue
                seen.add((tag, attr, value))
                if not value or EXTERNAL.match(value):
                    counts["external"] += 1 if value else 0
                    continue
                counts["internal"] += 1
                target, _, fragment = value.partition("#")
                target = urllib.parse.unquote(target.split("?", 1)[0])
                if target == "":
                    target_path = page_path
                elif target.startswith("/"):
                    target_path = os.path.join(book, target.lstrip("/"))
                else:
                    target_path = os.path.join(base_dir, target)
                target_path = os.path.realpath(target_path)
                if os.path.isdir(target_path):
                    target_path = os.path.join(target_path, "index.html")
                where = f"{rel_page}: <{tag} {attr}=\"{value}\">"
                inside = target_path == book or target_path.startswith(book + os.sep)
                # In a site (scripts/build_site.sh), the book may link to the pages beside it.
                site = os.path.dirname(book)
                in_site = SITE and target_path.startswith(site + os.sep) and os.path.isfile(target_path)
                if not inside and not in_site:
                    broken.append(f"{where}: outside the book")
                    continue
                if not os.path.isfile(target_path):
                    broken.append(f"{where}: no file {os.path.relpath(target_path, book)}")
                    continue
                fragment = urllib.parse.unquote(fragment)
                if fragment and target_path.endswith(".html"):
                    if fragment not in parse_html(target_path, cache).ids:
                        broken.append(
                            f"{where}: no element with id \"{fragment}\" in "
                            f"{os.path.relpath(target_path, book)}"
                        )
    return len(cache)


MD_LINK = re.compile(r"!?\[(?:[^\[\]]|\[[^\]]*\])*\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)")
MD_REF = re.compile(r"^\s*\[[^\]]+\]:\s*<?(\S+?)>?(?:\s+.*)?$", re.M)
HTML_ATTR = re.compile(r"<(?:img|a|source)\b[^>]*?\b(?:src|href)\s*=\s*\"([^\"]+)\"", re.I)
FENCE = re.compile(r"^(```|~~~).*?^\1[^\n]*$", re.M | re.S)


def github_slugs(markdown_text):
    """Anchors of the headings of a Markdown file, as GitHub makes them."""
    slugs, seen = set(), {}
    for line in FENCE.sub("", markdown_text).splitlines():
        m = re.match(r"^#{1,6}\s+(.*?)\s*#*\s*$", line)
        if not m:
            continue
        text = re.sub(r"[`*_]|<[^>]+>", "", m.group(1))
        text = re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", text)
        slug = re.sub(r"[^\w\- ]", "", text.strip().lower()).replace(" ", "-")
        n = seen.get(slug, 0)
        seen[slug] = n + 1
        slugs.add(slug if n == 0 else f"{slug}-{n}")
    return slugs


def check_markdown(md_path, repo, broken, counts):
    with open(md_path, encoding="utf-8") as f:
        text = f.read()
    body = FENCE.sub("", text)
    values = MD_LINK.findall(body) + MD_REF.findall(body) + HTML_ATTR.findall(body)
    rel_md = os.path.relpath(md_path, repo)
    for value in values:
        if EXTERNAL.match(value):
            counts["external"] += 1
            continue
        counts["internal"] += 1
        target, _, fragment = value.partition("#")
        target = urllib.parse.unquote(target)
        target_path = md_path if target == "" else os.path.join(os.path.dirname(md_path), target)
        target_path = os.path.normpath(target_path)
        if not os.path.exists(target_path):
            broken.append(f"{rel_md}: ({value}): no file {os.path.relpath(target_path, repo)}")
            continue
        if fragment and target_path.endswith(".md"):
            with open(target_path, encoding="utf-8") as f:
                if fragment not in github_slugs(f.read()):
                    broken.append(
                        f"{rel_md}: ({value}): no heading #{fragment} in "
                        f"{os.path.relpath(target_path, repo)}"
                    )


# Set by --site: links may leave the book into the site's folder.
SITE = False


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("book", nargs="?", help="the built book (default: out/book in the repository)")
    parser.add_argument("--repo", default=os.path.dirname(here), help="repository root (default: this script's ..)")
    parser.add_argument("--site", action="store_true",
                        help="the book is part of a site (scripts/build_site.sh puts it in OUT/book): "
                             "links to existing files of its parent folder are allowed")
    args = parser.parse_args()
    global SITE
    SITE = args.site
    repo = os.path.abspath(args.repo)
    book = os.path.abspath(args.book) if args.book else os.path.join(repo, "out", "book")
    if not os.path.isfile(os.path.join(book, "index.html")):
        print(f"error: {book} is not a built book (no index.html); run `mdbook build docs` first", file=sys.stderr)
        return 2

    broken = []
    counts = {"internal": 0, "external": 0}
    pages = check_book(book, broken, counts)
    readme = os.path.join(repo, "README.md")
    if os.path.isfile(readme):
        check_markdown(readme, repo, broken, counts)
    else:
        broken.append(f"README.md: not found in {repo}")
    # The scene folder's page points into the book too.
    scenes_readme = os.path.join(repo, "scenes", "README.md")
    if os.path.isfile(scenes_readme):
        check_markdown(scenes_readme, repo, broken, counts)

    for line in broken:
        print(f"broken: {line}")
    print(
        f"{pages} HTML pages, README.md and scenes/README.md: {counts['internal']} relative links checked, "
        f"{len(broken)} broken; {counts['external']} external links not fetched"
    )
    return 1 if broken else 0


if __name__ == "__main__":
    sys.exit(main())
