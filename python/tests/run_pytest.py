"""ctest's entry to the pytest suite: runs it with this interpreter and fails on every non-zero exit code,
pytest's 5 ("no tests were collected") included, and when numpy or pytest is missing (never a skip)."""
import importlib.util
import sys

for module in ("numpy", "pytest"):
    if importlib.util.find_spec(module) is None:
        sys.exit(f"run_pytest: {module} is missing for {sys.executable} (Debian: python3-{module}; see docs/python.md)")

import pytest  # noqa: E402

code = pytest.main(["-q", "-p", "no:cacheprovider", *sys.argv[1:]])
if code == 5:
    print("run_pytest: pytest collected no tests: failing", file=sys.stderr)
    sys.exit(1)
sys.exit(int(code))
