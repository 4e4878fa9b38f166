import os
import pathlib

import pytest

SOURCE = pathlib.Path(__file__).resolve().parents[2]
DATA = pathlib.Path(os.environ.get("CLEANMAP_SHARED_DATA", SOURCE.parent / "shared" / "data"))
BINARY = os.environ.get("CLEANMAP_BINARY", str(SOURCE / "build" / "apps" / "cleanmap"))


@pytest.fixture(scope="session")
def sk07():
    seq = DATA / "semantickitti" / "07"
    if not seq.is_dir():
        pytest.skip(f"{seq}: no shared data")
    return seq


@pytest.fixture(scope="session")
def preset():
    return SOURCE / "config" / "kitti-hdl64.yaml"
