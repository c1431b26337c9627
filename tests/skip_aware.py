"""unittest.main for the suite's Python tests, as ctest should see them: exit 77 (the tests' SKIP_RETURN_CODE
in tests/CMakeLists.txt) when nothing failed but something was skipped, so a skip shows as "Not Run"
in ctest's summary instead of passing silently; 1 on a failure; 0 when everything ran and passed."""
import sys
import unittest

SKIP_RETURN_CODE = 77


def main(**kwargs):
    result = unittest.main(exit=False, **kwargs).result
    if not result.wasSuccessful():
        sys.exit(1)
    if result.skipped:
        for test, reason in result.skipped:
            print(f"SKIPPED {test.id()}: {reason}", file=sys.stderr)
        sys.exit(SKIP_RETURN_CODE)
    sys.exit(0)
