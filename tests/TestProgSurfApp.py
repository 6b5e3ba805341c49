"""Document-level tests of ProgSurf, as FreeCAD's unit-test runner sees them.

`freecadcmd -t TestProgSurfApp` (registered in Init.py through FreeCAD.__unit_test__) and the
Test workbench load this module; `load_tests` gathers every `tests/app/test_*.py`.

Convention for tests/app: write `unittest.TestCase` classes (pytest runs them too), give each
test a fresh document and close it in tearDown, and skip with a reason (`self.skipTest`) when
something optional is absent, such as ../shared beside the checkout.
"""
import os
import unittest

APP_TESTS = os.path.join(os.path.dirname(os.path.abspath(__file__)), "app")


def load_tests(loader: unittest.TestLoader, standard_tests: unittest.TestSuite,
               pattern: str | None) -> unittest.TestSuite:
    """unittest's load_tests protocol: every test in tests/app/test_*.py."""
    suite = unittest.TestSuite()
    suite.addTests(standard_tests)
    suite.addTests(loader.discover(APP_TESTS, pattern="test_*.py", top_level_dir=APP_TESTS))
    return suite
