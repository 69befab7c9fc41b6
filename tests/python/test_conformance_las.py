"""Outputs hold what the input held, read by laspy: `skyground classify` on
every LAS/LAZ file of ../shared/data/conformance (SKYGROUND_CONFORMANCE_DATA
overrides) writes the producer's points with new classes in the version and
point format they need (LAS 1.4 and format 6+ when returns exceed 5 or
classes exceed 31; a 1.4 input stays 1.4), every other dimension (extra bytes
among them) and the CRS kept, as many points in the same order, no COPC
records, the waveform bits kept. A file the command refuses must be refused
by name with nothing written (the Rust conformance suite judges the message)."""
import os
import subprocess
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import laspy
import numpy as np
import pytest

from conftest import BIN, ROOT

CONF = Path(os.environ.get("SKYGROUND_CONFORMANCE_DATA", ROOT.parent / "shared" / "data" / "conformance"))
FILES = sorted(p for p in CONF.glob("*") if p.suffix.lower() in (".las", ".laz")) if CONF.is_dir() else []
# Legacy formats 0-5 -> the format 6-10 that holds the same fields.
EXTENDED = {0: 6, 1: 6, 2: 7, 3: 7, 4: 9, 5: 10}
WAVEFORM_BITS = 0b110


@pytest.fixture(scope="module")
def classified(tmp_path_factory):
    """Every file classified once, two at a time: {name: (returncode, stderr, output path)}."""
    out = tmp_path_factory.mktemp("conformance_las")

    def run(path):
        dest = out / f"{path.stem}.classified{path.suffix.lower()}"
        p = subprocess.run([str(BIN / "skyground"), "classify", "--in", str(path), "--out", str(dest)],
                           capture_output=True, text=True, timeout=300, stdin=subprocess.DEVNULL)
        return path.name, (p.returncode, p.stderr, dest)

    with ThreadPoolExecutor(max_workers=os.cpu_count() or 2) as pool:
        return dict(pool.map(run, FILES))


def needs_extended(las):
    """True when the points hold what point formats 0-5 cannot."""
    if las.header.point_count == 0:
        return False
    most = max(int(np.max(las.return_number)), int(np.max(las.number_of_returns)))
    return most > 5 or int(np.max(las.classification)) > 31


def vlr_ids(las):
    return [v.user_id for v in list(las.header.vlrs) + list(las.evlrs or [])]


def same_crs(a, b):
    try:
        ca = a.header.parse_crs()
    except Exception:  # noqa: BLE001 - laspy cannot resolve some producers' records
        return True
    if ca is None:
        return True
    cb = b.header.parse_crs()
    return cb is not None and (ca == cb or ca.to_epsg() == cb.to_epsg())


@pytest.mark.parametrize("path", FILES, ids=[p.name for p in FILES])
def test_classified_copy_keeps_what_the_input_held(path, classified):
    code, stderr, dest = classified[path.name]
    if code != 0:
        assert path.name in stderr and "panicked" not in stderr, stderr
        assert not dest.exists() and not Path(f"{dest}.part").exists()
        return
    src, out = laspy.read(path), laspy.read(dest)
    assert out.header.point_count == src.header.point_count
    upgraded = src.header.point_format.id < 6 and needs_extended(src)
    if upgraded:
        assert (out.header.version.major, out.header.version.minor) == (1, 4)
        assert out.header.point_format.id == EXTENDED[src.header.point_format.id]
    else:
        assert out.header.version == src.header.version
        assert out.header.point_format.id == src.header.point_format.id
    for axis in "xyz":
        scale = out.header.scales["xyz".index(axis)]
        assert np.allclose(getattr(src, axis), getattr(out, axis), atol=scale), axis
    kept = set(out.point_format.dimension_names)
    for dim in src.point_format.dimension_names:
        if dim in ("classification", "X", "Y", "Z") or (upgraded and dim not in kept):
            continue
        assert dim in kept, f"{dim} lost"
        a, b = np.asarray(src[dim]), np.asarray(out[dim])
        if upgraded and dim in ("scan_angle_rank", "scan_angle"):
            continue
        assert np.array_equal(a, b), f"{dim} changed"
    assert "copc" not in vlr_ids(out)
    assert int(out.header.global_encoding.value) & WAVEFORM_BITS == int(src.header.global_encoding.value) & WAVEFORM_BITS
    assert same_crs(src, out)


def test_the_folder_has_las_files():
    if not CONF.is_dir():
        pytest.skip(f"conformance data not found: {CONF}")
    assert FILES, f"{CONF}: no LAS/LAZ files"
