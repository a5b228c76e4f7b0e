"""Put the repository root on sys.path so acausal, components, library and examples import."""

import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

# The persistent compile cache stays off in the tests (a test must not depend on
# what an earlier run left in the user's cache folder); tests/compiler/test_diskcache.py
# turns it on, each test with a folder of its own.
import os  # noqa: E402

os.environ.setdefault("ACAUSAL_DISK_CACHE", "off")

# The compile cache's secret key lives in the user's configuration folder: the tests that
# turn the cache on get a folder of their own, not the real home's (which may be read-only).
import tempfile  # noqa: E402

os.environ.setdefault("XDG_CONFIG_HOME", tempfile.mkdtemp(prefix="acausal-tests-config-"))
