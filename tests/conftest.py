import os
import pytest


@pytest.fixture(autouse=True, scope="session")
def _isolated_cache(tmp_path_factory):
    """Tests never touch the user's cache unless FLEXBEARING_CACHE is set explicitly."""
    if "FLEXBEARING_CACHE" not in os.environ:
        os.environ["FLEXBEARING_CACHE"] = str(tmp_path_factory.mktemp("flexbearing-cache"))
    yield
