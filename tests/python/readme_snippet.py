"""Runs the README's Python snippet as written (issue 35): the first ```python block of
README.md, executed from the repository's top folder with the built package on the path.
Fails on any exception, and when the snippet mapped nothing."""
import os
import sys

source = os.environ["HAZMAP_SOURCE_DIR"]
with open(os.path.join(source, "README.md"), encoding="utf-8") as f:
    text = f.read()
begin = text.index("```python\n") + len("```python\n")
snippet = text[begin:text.index("```\n", begin)]
os.chdir(source)
scope = {"__name__": "__readme__"}
exec(compile(snippet, "README.md (Python snippet)", "exec"), scope)
import numpy as np  # noqa: E402  (after the snippet, which must import what it uses)
known = int(np.isfinite(scope["L0"].height).sum())
if known == 0:
    sys.exit("the README snippet mapped no cell")
print("README snippet ran: layer 0 has", known, "known cells")
