"""Models as data: a model built in Python runs bitwise like the model file; bad models raise the
right exception class with the key path of the wrong value."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import flexmbs
from conftest import EXAMPLES


def double_pendulum_in_python() -> flexmbs.Model:
    """examples/mbs/double_pendulum.toml, written out in Python."""
    link = lambda name, x: {  # noqa: E731
        "name": name,
        "type": "rigid",
        "mass": "1 kg",
        "inertia": [1e-4, 0.0834, 0.0834],
        "position": [x, 0, 0],
    }
    frame = lambda name, body, x=None: {  # noqa: E731
        "name": name,
        "body": body,
        **({"position": [x, 0, 0]} if x is not None else {}),
    }
    return flexmbs.Model.from_dict(
        {
            "model": {"name": "double_pendulum", "gravity": [0, "-9.81 m/s^2", 0]},
            "solver": {"type": "generalized-alpha", "rho_inf": 1.0, "h": "1 ms", "t_end": "2 s"},
            "body": [link("link1", "0.5 m"), link("link2", "1.5 m")],
            "frame": [
                frame("hinge", "ground"),
                frame("link1_top", "link1", "-0.5 m"),
                frame("link1_tip", "link1", "0.5 m"),
                frame("link2_top", "link2", "-0.5 m"),
                frame("link2_tip", "link2", "0.5 m"),
            ],
            "joint": [
                {"name": "shoulder", "type": "revolute", "a": "hinge", "b": "link1_top"},
                {"name": "elbow", "type": "revolute", "a": "link1_tip", "b": "link2_top"},
            ],
            "output": {
                "every": 10,
                "signals": ["link2_tip.position", "shoulder.force", "shoulder.reaction"],
            },
        }
    )


def assert_same_results(a: flexmbs.Results, b: flexmbs.Results) -> None:
    assert a.names() == b.names()
    assert np.array_equal(a.time, b.time)
    for group in flexmbs._results.GROUPS:
        assert np.array_equal(a.series(group), b.series(group), equal_nan=True), group


def test_python_model_is_bitwise_equal_to_the_file(tmp_path: Path) -> None:
    from_file = flexmbs.run(EXAMPLES / "double_pendulum.toml", out_dir=tmp_path / "file")
    from_python = flexmbs.run(double_pendulum_in_python(), out_dir=tmp_path / "python")
    assert from_file.status == from_python.status == "completed"
    assert from_file.rows == 201
    assert_same_results(from_file, from_python)


def test_numpy_values_are_bitwise_equal_to_lists(tmp_path: Path) -> None:
    """numpy arrays, numpy floats and integers in a model (converted through ``tolist()``) give
    the run of the same values as Python lists and floats, bit for bit."""
    def pendulum(vec, num, count) -> flexmbs.Model:
        m = double_pendulum_in_python()
        m["model.gravity"] = vec([0.0, -9.81, 0.0])
        m["solver.h"] = num(0.001)
        m["solver.t_end"] = num(0.2)
        m["solver.rho_inf"] = num(1.0)
        for k, x in enumerate([0.5, 1.5]):
            m[f"body[{k}].mass"] = num(1.0)
            m[f"body[{k}].position"] = vec([x, 0.0, 0.0])
            m[f"body[{k}].inertia"] = vec([1e-4, 0.0834, 0.0834])
        m["frame[link1_tip].position"] = vec([0.5, 0.0, 0.0])
        m["output.every"] = count(10)
        return m

    lists = pendulum(list, float, int)
    arrays = pendulum(np.array, np.float64, np.int64)
    assert isinstance(arrays["body[0].inertia"], np.ndarray) and type(arrays["solver.h"]) is np.float64
    assert arrays.to_toml() == lists.to_toml()
    a = flexmbs.run(lists, out_dir=tmp_path / "lists")
    b = flexmbs.run(arrays, out_dir=tmp_path / "arrays")
    assert a.status == b.status == "completed" and a.rows == 21
    assert_same_results(a, b)


def test_numpy_sweep_values_are_bitwise_equal_to_lists(spring: flexmbs.Model) -> None:
    outputs = ["max(mass.position.x)", "mass.position.x", "mean(energy/total)"]
    values = [50.0, 100.0, 400.0]
    lists = flexmbs.sweep(spring, {"load[spring].stiffness": values, "body[mass].mass": [1.0] * 3}, outputs, workers=2)
    arrays = flexmbs.sweep(
        spring,
        {"load[spring].stiffness": np.array(values), "body[mass].mass": np.ones(3, dtype=np.float64)},
        outputs,
        workers=2,
    )
    assert list(arrays["status"]) == ["completed"] * 3
    for key in ["load[spring].stiffness", "body[mass].mass", *outputs]:
        assert arrays[key].dtype == np.float64
        assert np.array_equal(arrays[key], lists[key]), key
    assert lists["mass.position.x"][0] != lists["mass.position.x"][2]  # the values took effect


def test_units_are_converted_by_the_model_compiler(tmp_path: Path) -> None:
    """`"1 ms"` and `0.001` (SI) give the same run, bit for bit; so do "2 s" and 2.0."""
    m = double_pendulum_in_python()
    m["solver.t_end"] = "0.2 s"
    si = m.copy()
    si["solver.h"] = 0.001
    si["solver.t_end"] = 0.2
    si["body[link1].position"] = [0.5, 0.0, 0.0]
    a = flexmbs.run(m, out_dir=tmp_path / "units")
    b = flexmbs.run(si, out_dir=tmp_path / "si")
    assert_same_results(a, b)


def test_dict_round_trip_and_key_paths(pendulum: flexmbs.Model) -> None:
    d = pendulum.to_dict()
    assert d["solver"]["h"] == "1 ms"
    assert pendulum["body[1].name"] == "link2"
    assert pendulum["body[link2].mass"] == "1 kg"
    assert pendulum["model.gravity"][1] == "-9.81 m/s^2"
    again = flexmbs.Model.from_toml(pendulum.to_toml())
    assert again == pendulum
    pendulum["body[link2].mass"] = "2 kg"
    assert pendulum["body[1].mass"] == "2 kg"
    assert d["body"][1]["mass"] == "1 kg"  # to_dict copied
    pendulum["solver.new_table.x"] = 1  # intermediate tables are created
    assert pendulum.data["solver"]["new_table"] == {"x": 1}
    pendulum["solver.new_table"] = None  # None removes a key
    assert "solver.new_table" not in pendulum
    with pytest.raises(flexmbs.ModelError) as e:
        pendulum["body[7].mass"]
    assert e.value.key_path == "body[7]"


def test_loaded_model_errors_name_file_and_line(tmp_path: Path) -> None:
    text = (EXAMPLES / "double_pendulum.toml").read_text()
    bad = tmp_path / "bad.toml"
    bad.write_text(text.replace('b = "link2_top"', 'b = "link3_top"'))
    expected_line = 1 + text.splitlines().index('b = "link2_top"')
    with pytest.raises(flexmbs.ModelError) as e:
        flexmbs.check(bad)
    assert e.value.key_path == "joint[1].b"
    assert e.value.file == str(bad)
    assert e.value.line == expected_line
    assert f"{bad}:{expected_line}:" in str(e.value)
    # the same model changed in Python: key path only (the lines of generated text mean nothing)
    m = flexmbs.load(bad)
    m["joint[1].name"] = "elbow2"
    with pytest.raises(flexmbs.ModelError) as e:
        flexmbs.check(m)
    assert e.value.key_path == "joint[1].b" and e.value.file is None and e.value.line is None


def test_toml_syntax_error_has_line(tmp_path: Path) -> None:
    bad = tmp_path / "syntax.toml"
    bad.write_text('[model]\nname = "x"\n[solver\n')
    with pytest.raises(flexmbs.ModelError) as e:
        flexmbs.load(bad)
    assert e.value.line == 3 and e.value.file == str(bad)


BAD_MODELS = [
    # (key path to set, value, error class, key path reported, words in the message)
    ("body[0].mass", "1 m", flexmbs.ModelError, "body[0].mass", "length unit"),
    ("body[1].mass", -1.0, flexmbs.ModelError, "body[1].mass", "must be > 0"),
    ("joint[0].b", "nowhere", flexmbs.ModelError, "joint[0].b", "unknown frame"),
    ("joint[1].type", "telepathic", flexmbs.ModelError, "joint[1].type", "unknown variant"),
    ("solver.h", "0 s", flexmbs.ModelError, "solver.h", "must be > 0"),
    ("solver.type", "euler", flexmbs.ModelError, "solver.type", "unknown variant"),
    ("model.gravity", [0, -9.81], flexmbs.ModelError, "model.gravity", "length 2"),
    ("frame[0].body", "nobody", flexmbs.ModelError, "frame[0].body", "unknown body"),
    ("body[0].colour", "red", flexmbs.ModelError, "body[0].colour", "unknown field"),
    ("output.signals", ["nonexistent.position"], flexmbs.ModelError, "output.signals[0]", "unknown frame"),
    ("body[0].mass", object(), flexmbs.ModelError, "body[0].mass", "cannot be written"),
    ("body[0].inertia", [1, 2], flexmbs.ModelError, "body[0].inertia", "three principal moments"),
    ("body[1].name", "link1", flexmbs.ModelError, "body[1].name", "duplicate name"),
    ("solver.t_end", "2 kg", flexmbs.ModelError, "solver.t_end", "mass unit"),
    ("model.name", None, flexmbs.ModelError, "model", "missing field `name`"),
    ("solver.rho_inf", 2.0, flexmbs.ModelError, "solver.rho_inf", "[0, 1]"),
    ("output.every", 0, flexmbs.ModelError, "output.every", ">= 1"),
]


@pytest.mark.parametrize("key,value,cls,path,words", BAD_MODELS, ids=[c[0] + "=" + repr(c[1])[:20] for c in BAD_MODELS])
def test_bad_model_raises_with_key_path(pendulum, key, value, cls, path, words) -> None:
    pendulum[key] = value
    with pytest.raises(cls) as e:
        flexmbs.check(pendulum)
    assert isinstance(e.value, flexmbs.Error)
    assert e.value.key_path == path
    assert words in str(e.value)


def test_invalid_key_path_is_a_model_error(pendulum: flexmbs.Model) -> None:
    with pytest.raises(flexmbs.ModelError):
        pendulum["body[0"] = 1


def test_solver_error_keeps_a_failed_results_file(pendulum: flexmbs.Model, tmp_path: Path) -> None:
    """Far too large a step: Newton fails; the file holds the steps before, status failed."""
    pendulum["solver.h"] = "0.5 s"
    pendulum["solver.t_end"] = "20 s"
    pendulum["output.every"] = 1
    with pytest.raises(flexmbs.SolverError) as e:
        flexmbs.run(pendulum, out_dir=tmp_path)
    err = e.value
    assert isinstance(err, flexmbs.Error)
    assert 0.0 <= err.t < 20.0 and err.h == pytest.approx(0.5)
    assert isinstance(err.hint, str) and "`h`" in err.hint, err.hint
    r = flexmbs.read_results(err.results)
    assert r.status == "failed" and r.status_time == pytest.approx(err.t)
    assert r.time[-1] <= err.t + 1e-12


def cardan_spin() -> flexmbs.Model:
    """A rigid body with Cardan angles spinning about y at pi/2 rad / 0.1 s: beta reaches 90 deg,
    where Cardan angles are singular, after 100 steps (crates/flexmbs-sim/tests/run.rs)."""
    return flexmbs.Model.from_dict(
        {
            "model": {"name": "cardan_spin"},
            "solver": {"type": "generalized-alpha", "h": "1 ms", "t_end": "0.2 s"},
            "body": [
                {
                    "name": "block",
                    "type": "rigid",
                    "mass": "2 kg",
                    "inertia": [0.01, 0.02, 0.03],
                    "angular_velocity": [0, "15.707963267948966 rad/s", 0],
                }
            ],
            "output": {"signals": ["block.orientation"]},
        }
    )


def test_solver_error_at_a_cardan_singularity(tmp_path: Path) -> None:
    """The run fails at t = 0.099 s (the step that would reach beta = 90 deg), naming the body,
    the Cardan singularity and quaternions; the results file keeps the 100 rows before."""
    with pytest.raises(flexmbs.SolverError) as e:
        flexmbs.run(cardan_spin(), out_dir=tmp_path)
    err = e.value
    assert isinstance(err, flexmbs.Error)
    assert err.t == pytest.approx(0.099, abs=1e-9) and err.h == pytest.approx(0.001, rel=1e-12)
    assert isinstance(err.residual, float)
    for part in ["block", "Cardan", "quaternion"]:
        assert part in str(err), str(err)
    assert err.results == str(tmp_path / "results.h5")
    assert isinstance(err.hint, str) and "`h`" in err.hint, err.hint  # the general hint
    r = flexmbs.read_results(err.results)
    assert r.status == "failed" and r.status_time == pytest.approx(err.t)
    assert "Cardan" in r.status_message and r.rows == 100
    beta = r.series("block.orientation.y")
    assert beta[-1] == pytest.approx(0.099 * 15.707963267948966, abs=1e-12)


def test_io_errors(tmp_path: Path) -> None:
    missing = tmp_path / "missing.h5"
    with pytest.raises(flexmbs.IoError) as e:
        flexmbs.read_results(missing)
    assert e.value.path == str(missing)
    not_h5 = tmp_path / "results.h5"
    not_h5.write_text("not hdf5")
    with pytest.raises(flexmbs.IoError) as e:
        flexmbs.read_results(not_h5)
    assert e.value.path == str(not_h5)
    with pytest.raises(flexmbs.IoError) as e:
        flexmbs.load(tmp_path / "missing.toml")
    assert e.value.path == str(tmp_path / "missing.toml")
    blocker = tmp_path / "file"
    blocker.write_text("")
    with pytest.raises(flexmbs.IoError) as e:
        flexmbs.run(EXAMPLES / "spring_damper.toml", out_dir=blocker / "sub")
    assert e.value.path is not None and e.value.path.startswith(str(blocker))
