#!/usr/bin/env python3
"""Self-test of check_docs.py: a small repository in a temporary directory, with
good and bad cases, and exactly the problems it must report.

usage: test_check_docs.py        (unittest; exit 0 when every case passes)

The fixtures never spell a Markdown name in full: "@md" stands for the suffix,
so that check_docs.py, run on the real repository, does not read this file's
deliberately broken names as the repository's own.
"""
import io
import os
import subprocess
import sys
import tempfile
import unittest
from contextlib import redirect_stderr, redirect_stdout

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import check_docs  # noqa: E402

FIXTURE = {
    "README@md": """\
# Fake project

## Good section

[a document](docs/X@md), [its part](docs/X@md#part-one), [this file](#good-section),
[a directory](src/), [the web](https://example.com/INTERFACE@md), [mail](mailto:a@example.com)
![an image](img/logo.png)

[broken](docs/missing@md)
[escaping](../shared/INTERFACE@md)
[bad anchor](docs/X@md#no-such-part)
![missing image](img/missing.png)
[into the build](build/notes@md)

```
[in a fence](nowhere@md) and ../shared/METHODS@md
```

Inline code is not a link: `[code](img/nothing.png)`. In prose, docs/X@md passes and
`../shared/METHODS@md` does not.

[ref]: docs/X@md#part-two
""",
    "docs/X@md": """\
# X

## Part one

Part two
--------

Back to [the top](../README@md#fake-project) and [a sibling](Y@md), the bare name Y@md.
""",
    "docs/Y@md": "# Y\n\n## Part one\n\n## Part one\n\nSee [the second](#part-one-1).\n",
    "img/logo.png": "",
    "src/a.hpp": """\
// Conventions (docs/X@md, "Part one").
// See INTERFACE@md and ../shared/METHODS@md.
// The design note docs/Y@md and the missing docs/Z@md.
// Generated: *@md files; https://example.com/METHODS@md is a URL.
// Absolute: /work/shared/INTERFACE@md.
""",
    "src/b.py": 'NAME = "{name}@md"  # not checked\nPATH = "docs/X@md"\nBARE = "Y@md"\n',
    "CMakeLists.txt": """\
# ${PROJECT_SOURCE_DIR}/docs/X@md is checked, ${PROJECT_SOURCE_DIR}/docs/W@md fails,
# ${CMAKE_BINARY_DIR}/gen@md is not checked, ${CMAKE_CURRENT_SOURCE_DIR}/README@md passes.
""",
    "tools/run.sh": "cat README@md ./docs/X@md docs/../../outside@md\n",
    "notes.txt": "INTERFACE@md in a text file is not read\n",
    # Not in the repository: never read.
    "build/notes@md": "[broken](nowhere@md)\n",
    "build/host/x.cpp": "// INTERFACE@md\n",
    "tests/fuzz/corpus_a/seed.py": "# INTERFACE@md\n",
    ".git/info/x.py": "# INTERFACE@md\n",
}

EXPECTED_TEXT = [
    ("README@md", 9, "link 'docs/missing@md': the repository holds no docs/missing@md"),
    ("README@md", 10, "link '../shared/INTERFACE@md' leaves the repository"),
    ("README@md", 11, "link 'docs/X@md#no-such-part': docs/X@md has no heading with the anchor #no-such-part"),
    ("README@md", 12, "link 'img/missing.png': the repository holds no img/missing.png"),
    ("README@md", 13, "link 'build/notes@md': the repository holds no build/notes@md"),
    ("README@md", 20, "'../shared/METHODS@md' leaves the repository"),
    ("src/a.hpp", 2, "'INTERFACE@md' is not a path in the repository: name it by its path in the repository"),
    ("src/a.hpp", 2, "'../shared/METHODS@md' leaves the repository"),
    ("src/a.hpp", 3, "'docs/Z@md': the repository holds no such file"),
    ("src/a.hpp", 5, "'/work/shared/INTERFACE@md' is an absolute path"),
    ("src/b.py", 3, "'Y@md' is not a path in the repository: name it by its path in the repository, e.g. docs/Y@md"),
    ("CMakeLists.txt", 1, "'docs/W@md': the repository holds no such file"),
    ("tools/run.sh", 1, "'docs/../../outside@md' leaves the repository"),
]
EXPECTED = [(f.replace("@md", ".md"), n, m.replace("@md", ".md")) for f, n, m in EXPECTED_TEXT]


def build(root, files):
    for rel, text in files.items():
        path = os.path.join(root, rel.replace("@md", ".md"))
        os.makedirs(os.path.dirname(path), exist_ok=True)
        with open(path, "w", encoding="utf-8") as f:
            f.write(text.replace("@md", ".md"))


class CheckDocs(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.root = self.tmp.name
        build(self.root, FIXTURE)

    def tearDown(self):
        self.tmp.cleanup()

    def test_reports_exactly_the_bad_cases(self):
        problems = check_docs.check(self.root)
        self.assertEqual([(f, n) for f, n, _ in problems], sorted((f, n) for f, n, _ in EXPECTED))
        for (f, n, message), (_, _, expected) in zip(sorted(problems), sorted(EXPECTED)):
            self.assertIn(expected, message, f"{f}:{n}")

    def test_bare_name_without_a_file_points_to_the_example(self):
        problems = check_docs.check(self.root)
        bare = [m for f, n, m in problems if (f, n) == ("src/a.hpp", 2) and m.startswith("'INTERFACE")]
        self.assertEqual(len(bare), 1)
        expected = "e.g. docs/INTERFACE@md (the repository holds no file named INTERFACE@md)"
        self.assertIn(expected.replace("@md", ".md"), bare[0])

    def test_prints_file_line_message_and_exits_1(self):
        out = io.StringIO()
        with redirect_stdout(out):
            status = check_docs.main(["check_docs.py", self.root])
        self.assertEqual(status, 1)
        lines = out.getvalue().splitlines()
        self.assertEqual(len(lines), len(EXPECTED))
        self.assertTrue(lines[0].startswith("CMakeLists.txt:1: "), lines[0])

    def test_a_clean_repository_passes(self):
        with tempfile.TemporaryDirectory() as clean:
            build(clean, {k: v for k, v in FIXTURE.items() if k in ("docs/X@md", "docs/Y@md")})
            build(clean, {"README@md": "# Fake project\n\nSee [X](docs/X@md#part-two).\n",
                          "src/c.cpp": "// docs/X@md, tests/../docs/Y@md\n"})
            self.assertEqual(check_docs.check(clean), [])

    def test_command_line(self):
        run = subprocess.run([sys.executable, os.path.join(HERE, "check_docs.py"), self.root],
                             capture_output=True, text=True, timeout=30)
        self.assertEqual(run.returncode, 1)
        self.assertEqual(len(run.stdout.splitlines()), len(EXPECTED))

    def test_bad_usage_exits_2(self):
        with redirect_stderr(io.StringIO()):
            self.assertEqual(check_docs.main(["check_docs.py", "a", "b"]), 2)
            self.assertEqual(check_docs.main(["check_docs.py", os.path.join(self.root, "no-such-dir")]), 2)


if __name__ == "__main__":
    unittest.main()
