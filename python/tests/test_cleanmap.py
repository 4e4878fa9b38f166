"""The Python module against the command line: same settings, same labels, same errors."""
import json
import subprocess

import numpy as np
import pytest

import cleanmap
from conftest import BINARY


def cli(*args):
    return subprocess.run([BINARY, *map(str, args)], check=True, capture_output=True, text=True)


def test_config_overrides_by_preset_key(preset):
    cfg = cleanmap.Config.from_preset(preset, scorer_threshold=0.3, mapping={"resolution": 0.25}, radius=0.9)
    d = cfg.to_dict()
    assert d["scorer"]["threshold"] == 0.3
    assert d["mapping"]["resolution"] == 0.25
    assert d["scorer"]["radius"] == 0.9
    # What `cleanmap config` prints for the same preset and options, byte for byte.
    printed = cli("config", "--config", preset, "--threshold", "0.3", "--resolution", "0.25", "--radius", "0.9").stdout
    assert cfg.to_yaml() == printed


def test_bad_settings_raise_with_the_cli_message(preset, tmp_path):
    with pytest.raises(ValueError, match="unknown setting 'no_such_key'"):
        cleanmap.Config.from_preset(no_such_key=1)
    with pytest.raises(ValueError, match=r"scorer.threshold: must be in \[0, 1\], not 2"):
        cleanmap.Config.from_preset(scorer_threshold=2.0)
    with pytest.raises(OSError, match="no such config file"):
        cleanmap.Config.from_preset(tmp_path / "missing.yaml")
    with pytest.raises(ValueError, match="must be an N x 3 array"):
        cleanmap.OnlineMapper().push(np.zeros((4, 2), np.float32))


def test_read_log_gives_numpy_scans(sk07):
    log = cleanmap.read_log(str(sk07))
    assert len(log) == 10
    s = next(iter(log))
    assert s.points.dtype == np.float32 and s.points.ndim == 2 and s.points.shape[1] == 3
    assert s.pose.shape == (4, 4) and s.labels.dtype == np.uint32 and len(s.labels) == len(s.points)
    assert s.times is None  # KITTI velodyne files carry no per-point time
    ref = np.fromfile(sk07 / "velodyne" / "000000.bin", np.float32).reshape(-1, 4)[:, :3]
    assert np.array_equal(s.points, ref)


def test_pushed_labels_equal_run_online_with_given_poses(sk07, preset, tmp_path):
    cli("run", "--input", sk07, "--out", tmp_path / "cli", "--config", preset, "--use-given-poses", "--online")
    mapper = cleanmap.OnlineMapper(cleanmap.Config.from_preset(preset))
    results = []
    for s in cleanmap.read_log(str(sk07)):
        results += mapper.push(s.points, times=s.times, pose=s.pose, stamp=s.stamp)
    results += mapper.finish()
    assert [r.index for r in results] == list(range(10))
    for r in results:
        labels = np.fromfile(tmp_path / "cli" / "labels" / f"{r.index:06d}.label", np.uint32)
        scores = np.fromfile(tmp_path / "cli" / "scores" / f"{r.index:06d}.bin", np.float32)
        assert r.labels.dtype == np.uint32 and np.array_equal(r.labels, labels)
        assert np.array_equal(r.scores, scores, equal_nan=True)
        assert (r.labels == 251).sum() > 0
    static = mapper.static_points()
    assert static.dtype == np.float32 and static.shape[1] == 3 and len(static) > 100000


def test_run_equals_the_cli_offline(sk07, preset, tmp_path):
    cli("run", "--input", sk07, "--out", tmp_path / "cli", "--config", preset, "--use-given-poses")
    summary = cleanmap.run(str(sk07), str(tmp_path / "py"), cleanmap.Config.from_preset(preset), use_given_poses=True)
    assert summary["complete"] is True and summary["mode"] == "offline"
    for i in range(10):
        a = (tmp_path / "cli" / "labels" / f"{i:06d}.label").read_bytes()
        b = (tmp_path / "py" / "labels" / f"{i:06d}.label").read_bytes()
        assert a == b
    on_disk = json.loads((tmp_path / "py" / "summary.json").read_text())
    assert on_disk["dynamic_points"] == summary["dynamic_points"]


def test_run_on_bad_input_raises_and_marks_the_summary(tmp_path):
    (tmp_path / "log").mkdir()
    (tmp_path / "log" / "000000.pcd").write_text("not a pcd")
    with pytest.raises(OSError, match="none.txt: no such file"):
        cleanmap.run(str(tmp_path / "log"), str(tmp_path / "out1"), poses=str(tmp_path / "none.txt"))
    (tmp_path / "log" / "poses.txt").write_text("1 0 0 0 0 1 0 0 0 0 1 0\n")
    with pytest.raises(ValueError) as e:
        cleanmap.run(str(tmp_path / "log"), str(tmp_path / "out2"), use_given_poses=True)
    assert "000000.pcd" in str(e.value)
    for out in ("out1", "out2"):
        summary = json.loads((tmp_path / out / "summary.json").read_text())
        assert summary["complete"] is False and summary["error"]


def test_mixed_poses_are_refused():
    mapper = cleanmap.OnlineMapper()
    pts = np.random.default_rng(0).uniform(-10, 10, (1000, 3)).astype(np.float32)
    mapper.push(pts, pose=np.eye(4))
    with pytest.raises(ValueError, match="give every scan a pose or none"):
        mapper.push(pts)


def test_georeferenced_poses_give_the_same_labels_near_a_local_origin(sk07, preset):
    # SemanticKITTI 07 pushed twice: as it is, and with every pose 500 km east and 5,000 km
    # north (UTM-like). The mapper works relative to the first pose rounded to the kilometre:
    # labels identical, result poses back in the pushed frame.
    offset = np.array([500000.0, 5000000.0, 0.0])
    runs = []
    for shift in (np.zeros(3), offset):
        mapper = cleanmap.OnlineMapper(cleanmap.Config.from_preset(preset))
        results = []
        for s in cleanmap.read_log(str(sk07)):
            pose = s.pose.copy()
            pose[:3, 3] = np.round(pose[:3, 3] * 256) / 256 + shift  # exact in double either way
            results += mapper.push(s.points, times=s.times, pose=pose, stamp=s.stamp)
        results += mapper.finish()
        runs.append((mapper.map_origin, results))
    assert np.array_equal(runs[0][0], np.zeros(3))
    assert np.array_equal(runs[1][0], offset)
    for near, far in zip(runs[0][1], runs[1][1]):
        assert np.array_equal(near.labels, far.labels)
        assert np.allclose(far.pose[:3, 3] - near.pose[:3, 3], offset, atol=1e-6)
