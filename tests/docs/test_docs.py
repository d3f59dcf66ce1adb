#!/usr/bin/python3
"""The documentation site builds without a warning and without a broken internal link.

usage: test_docs.py SOURCE_DIR HSBD_BINARY [PYTHON_MODULE_DIR]

1. A canary: two pages built with docs/conf.py, one linking to a missing page, one to a
   missing anchor, one to a missing file: the build must fail and name all three. This
   shows that the settings below turn each kind of broken link into a failure.
2. The site itself (docs/, Sphinx html builder, -W -n --keep-going): every warning fails,
   so every internal link, anchor, image, included file and autodoc entry resolves. With
   PYTHON_MODULE_DIR the module must import from there (the API page is then checked too).
3. README.md: every relative link and image names a file of the repository, and every
   #anchor a heading of that file (GitHub's slugs).
4. docs/cli.md holds what `hsbd --help` prints.
About 10-30 s (the Sphinx build), optimised build only.
"""
import os
import re
import subprocess
import sys
import tempfile

SRC, HSBD = os.path.abspath(sys.argv[1]), sys.argv[2]
MODULE = os.path.abspath(sys.argv[3]) if len(sys.argv) > 3 else None
failures = []


def fail(msg):
    failures.append(msg)
    print("FAIL:", msg)


def run_sphinx(srcdir, outdir, builder="html", env=None):
    cmd = [sys.executable, "-m", "sphinx", "-W", "-n", "--keep-going", "-q", "-b", builder,
           "-d", os.path.join(outdir, ".doctrees"), srcdir, outdir]
    return subprocess.run(cmd, capture_output=True, text=True, env=env)


try:
    import myst_parser  # noqa: F401
    import sphinx  # noqa: F401
except ImportError as e:
    print(f"FAIL: {e}: the documentation needs python3-sphinx and python3-myst-parser "
          "(scripts/install-deps)")
    sys.exit(1)

with tempfile.TemporaryDirectory() as tmp:
    # 1. the canary
    canary = os.path.join(tmp, "canary")
    os.mkdir(canary)
    with open(os.path.join(SRC, "docs", "conf.py")) as f:
        conf = f.read()
    with open(os.path.join(canary, "conf.py"), "w") as f:
        f.write(conf)
    with open(os.path.join(canary, "index.md"), "w") as f:
        f.write("# Canary\n\n```{toctree}\nother\n```\n\n[gone](missing-page.md) "
                "[no anchor](other.md#no-such-heading) [no file](../no-such-file.ini)\n")
    with open(os.path.join(canary, "other.md"), "w") as f:
        f.write("# Other\n\n## A heading\n\n[fine](index.md) [fine too](#a-heading)\n")
    env = dict(os.environ, HSBD_PYTHONPATH=os.path.join(tmp, "nowhere"))
    r = run_sphinx(canary, os.path.join(tmp, "canary-out"), "dummy", env)
    out = r.stdout + r.stderr
    if r.returncode == 0:
        fail("the canary with broken links built without an error: the check is blind")
    for target in ("missing-page.md", "other.md#no-such-heading", "../no-such-file.ini"):
        if target not in out:
            fail(f"the canary's broken link {target} was not reported:\n{out}")
    if "fine" in out:
        fail(f"the canary's good links were reported:\n{out}")

    # 2. the site
    env = dict(os.environ)
    if MODULE:
        env.update(HSBD_PYTHONPATH=MODULE, HSBD_DOCS_REQUIRE_MODULE="1")
    r = run_sphinx(os.path.join(SRC, "docs"), os.path.join(tmp, "html"), "html", env)
    if r.returncode != 0:
        fail("sphinx-build -W -n docs/ failed:\n" + r.stdout + r.stderr)
    else:
        print("site: built without warnings")
        if MODULE:
            with open(os.path.join(tmp, "html", "python-api.html")) as f:
                api = f.read()
            if "hsbd.Simulation" not in api:
                fail("the Python API page does not document hsbd.Simulation")


# 3. README.md's relative links
def slug(heading):  # GitHub's anchors: lower case, punctuation dropped, spaces to '-'
    return re.sub(r"[^\w\- ]", "", heading.strip().lower()).replace(" ", "-")


def anchors(path):
    with open(path) as f:
        text = re.sub(r"```.*?```", "", f.read(), flags=re.S)
    return {slug(m) for m in re.findall(r"^#{1,6} (.*)$", text, flags=re.M)}


with open(os.path.join(SRC, "README.md")) as f:
    readme = f.read()
links = re.findall(r"\]\(([^)\s]+)\)", readme) + re.findall(r'src="([^"]+)"', readme)
checked = 0
for link in links:
    if re.match(r"[a-z]+:", link):
        continue
    path, _, anchor = link.partition("#")
    target = os.path.join(SRC, path) if path else os.path.join(SRC, "README.md")
    if not os.path.exists(target):
        fail(f"README.md links to {link}: no such file")
    elif anchor and target.endswith(".md") and anchor not in anchors(target):
        fail(f"README.md links to {link}: no such heading in {path or 'README.md'}")
    checked += 1
print(f"README.md: {checked} relative links checked")

# 4. docs/cli.md against hsbd --help
usage = subprocess.run([HSBD, "--help"], capture_output=True, text=True).stdout
with open(os.path.join(SRC, "docs", "cli.md")) as f:
    cli = f.read()
block = re.search(r"```text\n(.*?)```", cli, flags=re.S)
if not block or block.group(1) != usage:
    fail("docs/cli.md's usage block differs from `hsbd --help`: copy its output there")
else:
    print("docs/cli.md: the usage block is hsbd --help's")

sys.exit(1 if failures else 0)
