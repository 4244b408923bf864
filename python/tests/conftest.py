import pathlib

import pytest

import dcol

# The installed package must be the one under test, not the source folder (which has no
# compiled extension): run pytest from the repository root or anywhere but python/.
if not hasattr(dcol, "_dcol"):
    raise ImportError(f"{dcol.__file__}: not an installed dcol (run pytest outside python/)")


@pytest.fixture(scope="session")
def capi():
    from capi import CApi

    c = CApi()
    yield c
    c.close()


def pytest_report_header(config):
    from capi import library_path

    return [f"dcol {dcol.__version__} from {pathlib.Path(dcol.__file__).parent}",
            f"C ABI from {library_path()}"]
