#!/usr/bin/env python3
"""The repository documents itself: every document it names, it holds.

usage: check_docs.py [ROOT]      (ROOT: the repository, default two levels up)

Prints one line per problem, "FILE:LINE: message" (FILE relative to ROOT), and
exits 1 when there is any, 0 when there is none, 2 on bad usage. Standard
library only; reads every file once.

Which files
  Every file under ROOT except those in the directory .git (or a .git file),
  in a top-level directory whose name starts with "build", and under
  tests/fuzz/corpus* (the fuzzers' inputs). A file in one of those places is
  not "in the repository" for the rules below either: a link into build/
  fails, because a fresh clone has no build/.
  Markdown files: *.md. Source files: *.hpp, *.cpp, *.h, *.c, *.py, *.sh,
  *.cmake, *.ld and CMakeLists.txt.

Rule 1, links in Markdown (every *.md)
  Read outside fenced code blocks (``` or ~~~) and outside inline code spans:
  inline links and images [text](target), ![alt](target), and reference
  definitions [label]: target.
  - http:, https: and mailto: targets are allowed as they are.
  - Any other scheme, and a target starting with //, fails.
  - Any other target is a path: relative to the Markdown file's directory, or
    to ROOT when it starts with "/" (as GitHub reads it). It must stay inside
    ROOT and name a file or directory the repository holds (percent-escapes
    decoded, "?query" ignored). A target that climbs out of ROOT fails.
  - A #fragment on a Markdown target (or on its own: this file) must be the
    anchor of a heading of that file, GitHub style: the heading's text with
    its inline markup removed (code backticks, emphasis stars, link and image
    syntax, HTML tags), lower case, every character that is not a letter, a
    digit, "_", "-" or a space removed, each space turned into "-"; a repeated
    anchor gets "-1", "-2", ... in order. ATX (#) and setext (=== / ---)
    headings count, and so do id="..." and name="..." in HTML tags. The match
    is exact. A fragment on a directory or on a file that is not Markdown is
    not checked (GitHub gives source files #L10-style anchors).

Rule 2, documents named in Markdown prose (every *.md)
  Outside fenced code blocks and outside the link targets of rule 1 (URLs
  removed), a path-like word ending in ".md" (code spans included) must name a
  Markdown file of the repository, read relative to the file's own directory
  or to ROOT. So "docs/INTERFACE.md" in README.md passes, and so does the
  bare name of a document in the same directory; a name that climbs out of
  ROOT fails. A word after a variable is read as in rule 3.

Rule 3, documents named in source files (comments, strings and code alike)
  A word is a maximal run of the characters A-Z a-z 0-9 _ . - / with any
  trailing dots removed. A word that ends in ".md" and has a name before the
  ".md" names a document, and must be its path relative to ROOT, of a file the
  repository holds: "docs/INTERFACE.md", "macros/REGISTER_MAP.md",
  "tests/fuzz/README.md". It fails when it is:
  - a bare file name the root does not hold (even one that exists in some
    directory: the message names that path);
  - a path the repository does not hold;
  - an absolute path, or a path that climbs out of ROOT with "..".
  Not checked: the inside of URLs (scheme://...); a name built at run time
  (nothing before ".md", as in "*.md" or "{name}.md"). A word right after a
  variable is read as CMake reads it: ${PROJECT_SOURCE_DIR}/, ${CMAKE_SOURCE_DIR}/
  and ${trueaxis_SOURCE_DIR}/ are ROOT, ${CMAKE_CURRENT_SOURCE_DIR}/ and
  ${CMAKE_CURRENT_LIST_DIR}/ the file's directory; after any other variable
  ($VAR/, ${VAR}/, $(...)/, $<...>/) the word is not checked, since the
  checker cannot know where it points.
"""
import os
import re
import sys
import urllib.parse

SOURCE_SUFFIXES = (".hpp", ".cpp", ".h", ".c", ".py", ".sh", ".cmake", ".ld")
SOURCE_NAMES = ("CMakeLists.txt",)
ALLOWED_SCHEMES = ("http", "https", "mailto")
ROOT_VARIABLES = ("PROJECT_SOURCE_DIR", "CMAKE_SOURCE_DIR", "trueaxis_SOURCE_DIR")
HERE_VARIABLES = ("CMAKE_CURRENT_SOURCE_DIR", "CMAKE_CURRENT_LIST_DIR")
EXAMPLE = "docs/INTERFACE.md"

WORD = re.compile(r"[A-Za-z0-9_./-]+")
URL = re.compile(r"[A-Za-z][A-Za-z0-9+.-]*://[^\s'\"<>()\[\]{}`]*")
SCHEME = re.compile(r"^([A-Za-z][A-Za-z0-9+.-]*):")
VARIABLE_BEFORE = re.compile(r"(?:\$\{(\w+)\}|\$\(([^()]*)\)|\$<[^<>]*>|\$(\w+))$")
FENCE = re.compile(r"^ {0,3}(`{3,}|~{3,})")
ATX = re.compile(r"^ {0,3}(#{1,6})(?:[ \t]+(.*?))?(?:[ \t]+#+)?[ \t]*$")
SETEXT = re.compile(r"^ {0,3}(=+|-+)[ \t]*$")
HTML_ID = re.compile(r"<[^>]*\b(?:id|name)\s*=\s*[\"']([^\"']+)[\"']", re.IGNORECASE)
CODE_SPAN = re.compile(r"(`+)(.+?)\1")
# [text](target "title"): one level of brackets in the text, one level of
# parentheses in the target.
INLINE_LINK = re.compile(
    r"!?\[(?:[^\[\]]|\[[^\[\]]*\])*\]"
    r"\(\s*(<[^>]*>|(?:[^\s()]|\([^\s()]*\))*)"
    r"(?:\s+(?:\"[^\"]*\"|'[^']*'|\([^()]*\)))?\s*\)")
REFERENCE_DEFINITION = re.compile(r"^ {0,3}\[[^\]]+\]:\s*(<[^>]*>|\S+)")


# ----------------------------------------------------------------------------
# The repository's files


def _skipped_dir(rel_dir):
    """True for a directory (relative, '/'-separated) whose files are not in the repository."""
    if not rel_dir or rel_dir == ".":
        return False
    parts = rel_dir.split("/")
    if ".git" in parts or parts[0].startswith("build"):
        return True
    return rel_dir.startswith("tests/fuzz/corpus")


class Repository:
    def __init__(self, root):
        self.root = os.path.abspath(root)
        self.files = set()  # relative, '/'-separated
        self.dirs = {""}
        for here, dirs, files in os.walk(self.root):
            rel = os.path.relpath(here, self.root).replace(os.sep, "/")
            rel = "" if rel == "." else rel
            kept = []
            for d in sorted(dirs):
                child = f"{rel}/{d}" if rel else d
                if not _skipped_dir(child):
                    kept.append(d)
                    self.dirs.add(child)
            dirs[:] = kept
            for f in files:
                if f == ".git":
                    continue
                self.files.add(f"{rel}/{f}" if rel else f)
        self.by_name = {}
        for f in self.files:
            self.by_name.setdefault(f.rsplit("/", 1)[-1], []).append(f)
        self._anchors = {}

    def holds(self, rel):
        return rel in self.files or rel in self.dirs

    def read(self, rel):
        with open(os.path.join(self.root, rel), encoding="utf-8", errors="replace") as f:
            return f.read().splitlines()

    def anchors(self, rel):
        if rel not in self._anchors:
            self._anchors[rel] = markdown_anchors(self.read(rel))
        return self._anchors[rel]

    def markdown_files(self):
        return sorted(f for f in self.files if f.endswith(".md"))

    def source_files(self):
        return sorted(f for f in self.files
                      if f.endswith(SOURCE_SUFFIXES) or f.rsplit("/", 1)[-1] in SOURCE_NAMES)


def resolve(base_dir, path):
    """The '/'-separated path of `path` read from `base_dir` (both relative to the
    root), or None when it climbs out of the root."""
    joined = f"{base_dir}/{path}" if base_dir else path
    parts = []
    for p in joined.split("/"):
        if p in ("", "."):
            continue
        if p == "..":
            if not parts:
                return None
            parts.pop()
        else:
            parts.append(p)
    return "/".join(parts)


# ----------------------------------------------------------------------------
# Markdown


def outside_fences(lines):
    """(line number, text) of every line outside fenced code blocks."""
    fence = None
    for number, line in enumerate(lines, 1):
        m = FENCE.match(line)
        if fence is None:
            if m:
                fence = m.group(1)
                continue
            yield number, line
        elif m and m.group(1)[0] == fence[0] and len(m.group(1)) >= len(fence) \
                and not line.strip().strip(fence[0]):
            fence = None


def heading_text(raw):
    text = re.sub(r"!\[([^\]]*)\]\([^)]*\)", r"\1", raw)  # images: their alt text
    text = re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", text)   # links: their text
    text = re.sub(r"\[([^\]]*)\]\[[^\]]*\]", r"\1", text)  # reference links
    text = re.sub(r"<[^>]+>", "", text)                     # HTML tags
    return text.replace("`", "").replace("*", "")


def slug(text):
    text = heading_text(text).strip().lower()
    text = "".join(c for c in text if c.isalnum() or c in "_- ")
    return text.replace(" ", "-")


def markdown_anchors(lines):
    anchors = set()
    counts = {}

    def add(text):
        s = slug(text)
        n = counts.get(s, 0)
        counts[s] = n + 1
        anchors.add(s if n == 0 else f"{s}-{n}")

    previous = None  # the previous line, when it could be a setext heading's text
    for _, line in outside_fences(lines):
        for m in HTML_ID.finditer(line):
            anchors.add(m.group(1))
        atx = ATX.match(line)
        setext = SETEXT.match(line)
        if atx:
            add(atx.group(2) or "")
            previous = None
        elif setext and previous is not None:
            add(previous)
            previous = None
        elif line.strip() and not line.lstrip().startswith(("|", ">", "-", "*", "+")) \
                and not re.match(r"^\s*\d+[.)]\s", line) and not line.startswith("    "):
            previous = line
        else:
            previous = None
    return anchors


def link_targets(line):
    """(target, start, end) of every inline link, image and reference definition."""
    masked = CODE_SPAN.sub(lambda m: " " * len(m.group(0)), line)
    found = [(m.group(1), m.start(), m.end()) for m in INLINE_LINK.finditer(masked)]
    d = REFERENCE_DEFINITION.match(masked)
    if d:
        found.append((d.group(1), d.start(), d.end()))
    return found


def check_link(repo, rel, target):
    """The problem with one link target of Markdown file `rel`, or None."""
    if target.startswith("<") and target.endswith(">"):
        target = target[1:-1].strip()
    if not target:
        return "empty link target"
    scheme = SCHEME.match(target)
    if scheme:
        if scheme.group(1).lower() in ALLOWED_SCHEMES:
            return None
        return f"link '{target}': only http(s) and mailto links may leave the repository"
    if target.startswith("//"):
        return f"link '{target}': write the scheme (https://) or a path in the repository"
    path, _, fragment = target.partition("#")
    path = urllib.parse.unquote(path.partition("?")[0])
    fragment = urllib.parse.unquote(fragment)
    base = os.path.dirname(rel).replace(os.sep, "/")
    if path.startswith("/"):
        resolved = resolve("", path)
    elif path:
        resolved = resolve(base, path)
    else:
        resolved = rel
    if resolved is None:
        return f"link '{target}' leaves the repository: a clone holds only the repository"
    if not repo.holds(resolved):
        return f"link '{target}': the repository holds no {resolved or '/'}"
    if fragment and resolved.endswith(".md") and resolved in repo.files:
        if fragment not in repo.anchors(resolved):
            return f"link '{target}': {resolved} has no heading with the anchor #{fragment}"
    return None


def check_markdown(repo, rel):
    problems = []
    lines = repo.read(rel)
    base = os.path.dirname(rel)
    for number, line in outside_fences(lines):
        links = link_targets(line)
        for target, _, _ in links:
            problem = check_link(repo, rel, target)
            if problem:
                problems.append((rel, number, problem))
        # Rule 2: the prose without its links and URLs.
        prose = list(line)
        for _, start, end in links:
            prose[start:end] = " " * (end - start)
        prose = URL.sub(lambda m: " " * len(m.group(0)), "".join(prose))
        for word, before in document_words(prose):
            if word.startswith("/") and VARIABLE_BEFORE.search(before):
                problem = check_source_word(repo, rel, word, before)
                if problem:
                    problems.append((rel, number, problem))
                continue
            here = None if word.startswith("/") else resolve(base, word)
            top = None if word.startswith("/") else resolve("", word)
            if (here is not None and here in repo.files) or (top is not None and top in repo.files):
                continue
            problems.append((rel, number, word_problem(repo, word, here if top is None else top)))
    return problems


# ----------------------------------------------------------------------------
# Documents named in words


def document_words(line):
    """(word, text before it) of every word of `line` that names a .md document."""
    for m in WORD.finditer(line):
        word = m.group(0).rstrip(".")
        if not word.endswith(".md"):
            continue
        name = word.rsplit("/", 1)[-1]
        if name == ".md":
            continue  # built at run time ("*.md", "{name}.md")
        yield word, line[:m.start()]


def name_it(repo, word):
    """The advice every failure of rules 2 and 3 ends with."""
    name = word.rsplit("/", 1)[-1]
    paths = sorted(repo.by_name.get(name, []))
    if paths:
        return f"name it by its path in the repository, e.g. {paths[0]}"
    return f"name it by its path in the repository, e.g. {EXAMPLE} (the repository holds no file named {name})"


def word_problem(repo, word, resolved):
    """The message for a document word that `resolved` (None: outside the root) does not find."""
    if word.startswith("/"):
        return f"'{word}' is an absolute path: {name_it(repo, word)}"
    if resolved is None:
        return f"'{word}' leaves the repository, which is all a clone holds: {name_it(repo, word)}"
    if "/" not in word.strip("./"):
        return f"'{word}' is not a path in the repository: {name_it(repo, word)}"
    return f"'{word}': the repository holds no such file: {name_it(repo, word)}"


def check_source_word(repo, rel, word, before):
    """The problem with one document word of source file `rel`, or None."""
    variable = VARIABLE_BEFORE.search(before) if word.startswith("/") else None
    if variable:
        name = variable.group(1)
        if name in ROOT_VARIABLES:
            resolved = resolve("", word)
        elif name in HERE_VARIABLES:
            resolved = resolve(os.path.dirname(rel), word)
        else:
            return None  # another variable: where it points is not known here
        if resolved is not None and resolved in repo.files:
            return None
        return word_problem(repo, word.lstrip("/"), resolved)
    resolved = None if word.startswith("/") else resolve("", word)
    if resolved is not None and resolved in repo.files:
        return None
    return word_problem(repo, word, resolved)


def check_source(repo, rel):
    problems = []
    for number, line in enumerate(repo.read(rel), 1):
        if ".md" not in line:
            continue
        text = URL.sub(lambda m: " " * len(m.group(0)), line)
        for word, before in document_words(text):
            problem = check_source_word(repo, rel, word, before)
            if problem:
                problems.append((rel, number, problem))
    return problems


# ----------------------------------------------------------------------------


def check(root):
    """Every problem under `root` as (file, line, message), in file and line order."""
    repo = Repository(root)
    problems = []
    for rel in repo.markdown_files():
        problems += check_markdown(repo, rel)
    for rel in repo.source_files():
        problems += check_source(repo, rel)
    return sorted(problems, key=lambda p: (p[0], p[1]))


def main(argv):
    if len(argv) > 2 or (len(argv) == 2 and argv[1].startswith("-")):
        print("usage: check_docs.py [ROOT]", file=sys.stderr)
        return 2
    root = argv[1] if len(argv) == 2 else os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
    if not os.path.isdir(root):
        print(f"check_docs.py: {root}: not a directory", file=sys.stderr)
        return 2
    problems = check(root)
    for rel, number, message in problems:
        print(f"{rel}:{number}: {message}")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
