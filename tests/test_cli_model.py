"""The real ``rlff data synth thesis``, ``rlff fit`` and ``rlff generate`` commands.

The chain runs through the installed entry point in subprocesses; the many option checks call the
same command line in-process (``rlff.cli.main``), which saves a Python start-up per case.
"""

from __future__ import annotations

import json
import re

import numpy as np
import pandas as pd
import pytest

pytestmark = pytest.mark.integration


@pytest.fixture(scope="module")
def thesis_files(tmp_path_factory):
    from tests.conftest import run_cli

    folder = tmp_path_factory.mktemp("thesis")
    data, model = folder / "data.csv", folder / "model.json"
    made = run_cli("data", "synth", "thesis", "-o", str(data))
    assert made.code == 0, made.stderr
    fitted = run_cli("fit", str(data), "-o", str(model), "--max-components", "4", "--json")
    assert fitted.code == 0, fitted.stderr
    return data, model, json.loads(fitted.stdout)


def test_synth_fit_generate_chain(thesis_files, cli, rlff, tmp_path):
    data, model, summary = thesis_files
    frame = pd.read_csv(data)
    assert list(frame.columns[:4]) == ["trajectory", "angle", "distance", "velocity"] and len(frame) == 550
    assert summary["n_samples"] == 550 and summary["inputs"] == ["angle", "distance"]
    assert [row["n_components"] for row in summary["selection"]] == [1, 2, 3, 4]
    best = min(summary["selection"], key=lambda row: row["bic"])
    assert summary["n_components"] == best["n_components"]
    curves = {}
    for distance in ("4.5", "8.5", "12.5"):
        out = tmp_path / f"traj-{distance}.csv"
        run = cli if distance == "12.5" else rlff  # one through the entry point is enough
        result = run("generate", str(model), "--context", f"distance={distance}", "-o", str(out), "--json")
        assert result.code == 0, result.stderr
        report = json.loads(result.stdout)
        assert report["points"] == 100 and report["context"] == {"distance": float(distance)}
        curves[distance] = pd.read_csv(out)
    for name in ("angle", "velocity", "time", "pdf", "exploration", "gmr_mean"):
        assert name in curves["4.5"].columns
    velocities = np.array([curves[d]["velocity"].to_numpy() for d in ("4.5", "8.5", "12.5")])
    assert np.all(np.diff(velocities, axis=0) > 0)


def test_fit_prints_the_bic_table(thesis_files, rlff, tmp_path):
    data, _, _ = thesis_files
    result = rlff("fit", str(data), "-o", str(tmp_path / "m.json"), "--max-components", "3", "--seed", "1")
    assert result.code == 0, result.stderr
    assert "BIC" in result.stdout and "K =" in result.stdout
    fixed = rlff("fit", str(data), "-o", str(tmp_path / "k2.json"), "--components", "2", "--json")
    assert json.loads(fixed.stdout)["n_components"] == 2 and json.loads(fixed.stdout)["selection"] is None


def test_fit_progress_names_the_k_being_fitted(thesis_files, rlff, tmp_path):
    # the bar counted the K tried ("fitting: 3 of 8 values of K tried"), and a large K takes ten
    # times a small one's time: it sat at the last ones as if stuck, not saying which it fitted
    data, _, _ = thesis_files
    result = rlff("fit", str(data), "-o", str(tmp_path / "m.json"), "--max-components", "5", "--json")
    assert result.code == 0, result.stderr
    tried = [row["n_components"] for row in json.loads(result.stdout)["selection"]]  # stdout: the JSON alone
    said = [re.sub(r" \d+:\d\d:\d\d$", "", line) for line in result.stderr.splitlines()
            if re.search(r" \d+/5 \(\d+ %\) \d+:\d\d:\d\d$", line)]
    assert said == [*(f"fitting K = {k} (1 to 5 in turn) {k - 1}/5 ({20 * (k - 1)} %)" for k in tried),
                    "fitted K = 1 to 5 5/5 (100 %)"], result.stderr
    fixed = rlff("fit", str(data), "-o", str(tmp_path / "k2.json"), "--components", "2")
    assert fixed.code == 0 and "fitting K = 2 0/1 (0 %)" in fixed.stderr and "fitted K = 2 1/1 (100 %)" in fixed.stderr, \
        fixed.stderr


def test_fit_table_ln_l_is_the_one_bic_counts(rlff, tmp_path):
    """With effective samples BIC scales ln L by n_e / n: the table's ln L is that one, so that
    -2 ln L + p ln n_e gives its BIC, as the BIC figure's legend says."""
    from rlff.dataset import Dataset, Trajectory, write_csv
    from rlff.preprocess import densify

    rng = np.random.default_rng(1)
    throws = [Trajectory(f"t{i}", {"angle": np.linspace(0.7, 2.8, 6), "distance": np.full(6, 1.0 + 0.5 * (i % 3)),
                                   "velocity": 6 * np.sin(np.linspace(0.7, 2.8, 6)) + rng.normal(0, 0.3, 6)})
              for i in range(12)]
    data = tmp_path / "dense.csv"
    write_csv(densify(Dataset(throws), step=0.01)[0], data)
    result = rlff("fit", str(data), "-o", str(tmp_path / "m.json"), "--max-components", "2",
                  "--effective-samples", "50")
    assert result.code == 0, result.stderr
    rows = [line.strip("│ ").split("│") for line in result.stdout.splitlines() if line.startswith("│")]
    for k, bic, _, ln_l, _ in rows:
        parameters = int(k.strip(" *")) * (3 + 6) + int(k.strip(" *")) - 1
        assert -2 * float(ln_l) + parameters * np.log(50) == pytest.approx(float(bic), abs=0.02)
    assert "ln L scaled by 50 effective samples / " in result.stdout


@pytest.mark.parametrize(("name", "text", "said"), [
    # "not valid JSON (line 2, column 1: Extra data)"
    ("attempts.jsonl", '{"format": "rlff-attempts", "version": 1, "run": {}}\n{"attempt": 1}\n',
     "is an attempts log (rlff learn --log writes it), not a model"),
    # both were called datasets and told to be fitted, which fit refuses
    ("traj.csv", "angle,velocity,time,pdf,exploration,gmr_mean,gmr_std\n0.6,3.6,0,0.01,0.9,2.2,2.9\n",
     "is text (its first line: 'angle,velocity,time,pdf,exploration,gmr_mean,gmr_std'), not a model"),
    ("a06_s01_e01_skeleton3D.txt", "-0.357118 0.362846 2.671804 1.000000\n",
     "is text (its first line: '-0.357118 0.362846 2.671804 1.000000'), not a model"),
])
def test_another_file_given_as_the_model_says_what_it_is(rlff, tmp_path, name, text, said):
    path = tmp_path / name
    path.write_text(text)
    result = rlff("generate", str(path), "--context", "distance=2", "-o", str(tmp_path / "t.csv"))
    assert result.code == 2 and len(result.stderr.strip().splitlines()) == 1
    assert f"{path} {said} (model.json, which rlff fit writes)" in result.stderr, result.stderr


def test_a_dataset_given_as_the_model_says_to_fit_one_first(thesis_files, rlff, tmp_path):
    data, _, _ = thesis_files
    result = rlff("generate", str(data), "--context", "distance=2", "-o", str(tmp_path / "t.csv"))
    assert result.code == 2 and len(result.stderr.strip().splitlines()) == 1
    assert (f"{data}: a dataset, not a model (model.json): fit one first, rlff fit {data} -o model.json"
            in result.stderr), result.stderr
    garbage = tmp_path / "m.json"
    garbage.write_text("{ nope")
    assert "not valid JSON" in rlff("generate", str(garbage), "--context", "distance=2", "-o",
                                    str(tmp_path / "t.csv")).stderr


def test_fit_warns_for_a_given_k_with_more_parameters_than_samples(thesis_files, rlff, tmp_path):
    data, _, _ = thesis_files
    # 39 parameters at K = 4, 20 samples counted; the automatic choice says as much for its K
    result = rlff("fit", str(data), "-o", str(tmp_path / "m.json"), "-k", "4", "--effective-samples", "20")
    assert result.code == 0, result.stderr
    assert "the given K = 4 has 39 parameters, more than the 20 effective samples BIC counts" in result.stderr
    assert "K = 4 given, 550 samples" in result.stdout and "chosen" not in result.stdout
    auto = rlff("fit", str(data), "-o", str(tmp_path / "m.json"), "--max-components", "2")
    assert "K = 2 chosen" in auto.stdout and "K = 2 given" not in auto.stdout


def test_generate_options(thesis_files, rlff, tmp_path):
    _, model, _ = thesis_files
    out = tmp_path / "traj.csv"
    result = rlff(
        "generate", str(model), "--context", "distance=2.5", "--grid", "angle=1:9:17", "--exploration", "0",
        "--continuity", "-o", str(out),
    )
    assert result.code == 0, result.stderr
    frame = pd.read_csv(out)
    np.testing.assert_allclose(frame["angle"], np.linspace(1, 9, 17))
    assert np.all(frame["exploration"] == 0)
    assert np.all(np.diff(frame["time"]) > 0)


@pytest.mark.parametrize(("args", "message"), [
    (["--robot", "mine.toml"], "--robot mine.toml goes with --joints (its [whole_arm] table maps them) or --bearing "
                               "(checked against its turning joint): without them the path is the same for every "
                               "robot, mapped to the arm by `rlff robot export --robot mine.toml`; add --joints, or "
                               "drop --robot"),
    (["--exploration", "0.3", "--exploration-scale", "2"],
     "--exploration-scale sizes the exploration of --exploration auto; a fixed --exploration 0.3 does not use it: "
     "drop one of them"),
])
def test_generate_refuses_an_option_that_only_matters_beside_another(thesis_files, rlff, tmp_path, args, message):
    # both were ignored: the path was the same with any --robot, and with any --exploration-scale
    _, model, _ = thesis_files
    out = tmp_path / "t.csv"
    result = rlff("generate", str(model), "-c", "distance=2.5", *args, "-o", str(out))
    assert result.code == 2 and result.stderr.strip() == f"rlff: error: {message}", result.stderr
    assert not out.exists()


def test_generate_takes_robot_with_bearing_and_exploration_scale_with_auto(thesis_files, rlff, tmp_path):
    _, model, _ = thesis_files
    for args in (["--robot", "comau_smart5_six", "--bearing", "10"], ["--exploration", "auto", "--exploration-scale", "2"]):
        result = rlff("generate", str(model), "-c", "distance=2.5", *args, "-o", str(tmp_path / "t.csv"))
        assert result.code == 0, result.stderr


@pytest.mark.parametrize(
    "args,message",
    [
        (["--context", "height=2"], "unknown context 'height'"),
        ([], "missing context 'distance'"),
        (["--context", "distance=near"], "not a number"),
        (["--context", "distance=2", "--grid", "speed=0:1:5"], "path variable"),
        (["--context", "distance=2", "--grid", "angle=0:1"], "START:STOP:N"),
        (["--context", "distance=2", "--exploration", "2"], "a number in [0, 1]"),
    ],
)
def test_generate_bad_options_exit_2_with_one_line(thesis_files, rlff, tmp_path, args, message):
    _, model, _ = thesis_files
    result = rlff("generate", str(model), *args, "-o", str(tmp_path / "t.csv"))
    assert result.code == 2
    assert message in result.stderr
    assert len(result.stderr.strip().splitlines()) == 1


def test_fit_context_resolution(thesis_files, rlff, tmp_path):
    data, _, summary = thesis_files
    assert summary["context_resolution"] == {"distance": 1.0}  # auto: the thesis' baskets 1 unit apart
    given = rlff("fit", str(data), "-o", str(tmp_path / "m.json"), "-k", "3", "--context-resolution", "0.5", "--json")
    assert given.code == 0, given.stderr
    assert json.loads(given.stdout)["context_resolution"] == {"distance": 0.5}
    saved = json.loads((tmp_path / "m.json").read_text())
    assert saved["fit"]["context_resolution"] == {"distance": 0.5}
    assert min(c[1][1] for c in saved["covariances"]) >= 0.5**2 / 12
    for bad in ("fine", "-1", "inf"):
        result = rlff("fit", str(data), "-o", str(tmp_path / "x.json"), "--context-resolution", bad)
        assert result.code == 2 and "--context-resolution" in result.stderr and "fitting" not in result.stderr
        assert not (tmp_path / "x.json").exists()


def test_fit_effective_samples(rlff, tmp_path):
    from rlff.dataset import Dataset, Trajectory, write_csv
    from rlff.preprocess import densify

    rng = np.random.default_rng(0)
    throws = []
    for i in range(12):
        angle = np.linspace(0.7, 2.8, 6)
        distance = 1.0 + 0.5 * (i % 3)
        velocity = (1.0 + 0.4 * distance) * 6 * np.sin(angle) + rng.normal(0, 0.3, 6)
        throws.append(Trajectory(f"t{i}", {"angle": angle, "distance": np.full(6, distance), "velocity": velocity}))
    dense, _ = densify(Dataset(throws), step=0.01)
    data = tmp_path / "dense.csv"
    write_csv(dense, data)
    measured = rlff("fit", str(data), "-o", str(tmp_path / "m.json"), "--max-components", "3",
                    "--effective-samples", "measured", "--json")
    assert measured.code == 0, measured.stderr
    assert json.loads(measured.stdout)["effective_samples"] == pytest.approx(72)  # 12 throws x 6 samples
    text = rlff("fit", str(data), "-o", str(tmp_path / "m.json"), "-k", "2", "--effective-samples", "50")
    assert "BIC over 50 effective samples" in text.stdout
    default = rlff("fit", str(data), "-o", str(tmp_path / "m.json"), "-k", "2", "--json")
    assert json.loads(default.stdout)["effective_samples"] == pytest.approx(72)  # measured by default
    plain = rlff("fit", str(data), "-o", str(tmp_path / "m.json"), "-k", "2", "--effective-samples", "all", "--json")
    assert json.loads(plain.stdout)["effective_samples"] is None
    assert "hardly decide K" not in measured.stderr  # 72 measured samples, at most 29 parameters (K = 3)
    few = rlff("fit", str(data), "-o", str(tmp_path / "m.json"), "--max-components", "3", "--effective-samples", "5")
    assert few.code == 0 and "BIC rests on 5 effective samples, fewer than the" in few.stderr
    # K beyond what the samples BIC counts support is not tried: --max-components 100000 ran for
    # hours on 2,215 samples, its progress bar counting to 100000; since 2026-12-07 one component
    # per 4 samples over 3 columns (a covariance needs D + 1), before one per sample
    capped = rlff("fit", str(data), "-o", str(tmp_path / "m.json"), "--max-components", "100000",
                  "--effective-samples", "20", "--json")
    assert capped.code == 0, capped.stderr
    assert [row["n_components"] for row in json.loads(capped.stdout)["selection"]] == [1, 2, 3, 4, 5]
    # said with the count, the one the summary gives (it said "up to 69 only, the effective samples"
    # beside "BIC over 70 effective samples")
    assert ("--max-components 100000: K is tried up to 5 only: BIC counts 20 effective samples (--effective-samples) "
            "(a component needs 4 for a covariance over the 3 columns)") in capped.stderr
    # a K given outright beyond them is fitted, with a word
    fixed = rlff("fit", str(data), "-o", str(tmp_path / "m.json"), "-k", "8", "--effective-samples", "20")
    assert fixed.code == 0 and ("-k/--components 8 is more than the 20 effective samples (--effective-samples) of "
                                f"{data} support (5 at most over 3 columns)") in fixed.stderr
    bad = rlff("fit", str(data), "-o", str(tmp_path / "m.json"), "--effective-samples", "some")
    assert bad.code == 2 and "--effective-samples" in bad.stderr


def test_fit_and_generate_refuse_bad_files(thesis_files, cli, rlff, tmp_path):
    data, model, _ = thesis_files
    bad = rlff("fit", str(data), "-o", str(tmp_path / "m.json"), "--outputs", "speed")
    assert bad.code == 2 and "no column 'speed'" in bad.stderr
    document = json.loads(model.read_text())
    document["weights"][0] += 0.5
    broken = tmp_path / "broken.json"
    broken.write_text(json.dumps(document))
    result = cli("generate", str(broken), "--context", "distance=2", "-o", str(tmp_path / "t.csv"))
    assert result.code == 2 and "field 'weights'" in result.stderr
    nan_data = tmp_path / "nan.csv"
    nan_data.write_text("trajectory,angle,distance,velocity\na,0,1,0\na,1,1,nan\n")
    result = rlff("fit", str(nan_data), "-o", str(tmp_path / "m.json"))
    assert result.code == 2 and "velocity" in result.stderr


@pytest.mark.parametrize(("name", "text", "kind"), [
    ("a06_s01_e01_skeleton3D.txt", "".join(f"0.{j} 0.2 2.5 1\n" for j in range(40)), "MSR Action3D text"),
    ("take.csv", "time,right_shoulder_x,right_shoulder_y\n0,0.1,0.2\n", "joint CSV"),
])
@pytest.mark.parametrize("command", [
    ("fit", "{path}", "-o", "{out}.json"),
    ("learn", "{path}", "--basket", "1.5", "--log", "{out}.jsonl"),
    ("data", "preprocess", "{path}", "-o", "{out}.csv"),
])
def test_a_recording_given_as_demonstrations_says_to_import_it(rlff, tmp_path, name, text, kind, command):
    # an MSR file was read as a thesis matrix: "line 2: context row 'distance' is not constant"
    path = tmp_path / name
    path.write_text(text)
    result = rlff(*(arg.format(path=path, out=tmp_path / "out") for arg in command))
    assert result.code == 2
    assert f"a skeleton recording ({kind}), not demonstrations: import it first" in result.stderr


@pytest.mark.parametrize("command", [
    ("fit", "{path}", "-o", "{out}.json"),
    ("learn", "{path}", "--basket", "1.5", "--log", "{out}.jsonl"),
    ("data", "preprocess", "{path}", "-o", "{out}.csv"),
])
def test_a_generated_path_given_as_demonstrations_says_what_it_is(rlff, tmp_path, command):
    # its gmr_mean_shoulder_velocity column passed for a skeleton's: "a skeleton recording (joint CSV) ..."
    path = tmp_path / "traj.csv"
    path.write_text("angle,velocity,shoulder,shoulder_velocity,time,gmr_mean,gmr_mean_shoulder_velocity\n"
                    "0.6,3.6,2.3,3.2,0,2.2,3.1\n0.7,3.9,2.4,3.3,0.03,2.4,3.2\n")
    result = rlff(*(arg.format(path=path, out=tmp_path / "out") for arg in command))
    assert result.code == 2 and len(result.stderr.strip().splitlines()) == 1, result.stderr
    assert f"{path} is a generated path (rlff generate writes it), not demonstrations, which rlff data import " \
        "writes from recordings" in result.stderr


def _demos_in_other_units(path, distances, per_metre: float):
    """Demonstrations (3 throws at each of ``distances``, 4 samples each) whose distance column is
    in another unit (``per_metre`` of them a metre), their velocities as the metres would give."""
    rows = ["trajectory,angle,velocity,distance"] + [
        f"t{d}_{k},{a:.2f},{(1 + a) * d / per_metre:.3f},{d}" for d in distances for k in range(3)
        for a in (0.5, 1.0, 1.5, 2.0)]
    path.write_text("\n".join(rows) + "\n")
    return path


def test_distances_in_centimetres_are_refused_before_a_model_nobody_can_ask(rlff, tmp_path):
    # fit took 75-275 (cm) without a word; generate then refused 150 m and extrapolated at 1.5 m
    data = _demos_in_other_units(tmp_path / "cm.csv", (75, 150, 275), per_metre=100)
    result = rlff("fit", str(data), "-o", str(tmp_path / "m.json"))
    assert result.code == 2
    assert "column 'distance' holds 75 to 275, outside the basket distances 0.3 to 20 m (centimetres?" in result.stderr
    assert not (tmp_path / "m.json").exists()


def test_fit_refuses_demonstrations_without_a_basket_distance(rlff, tmp_path):
    # fit took (angle, velocity) alone by default: a model that threw the same for every basket,
    # which generate -c distance=2 then refused with "the model's context: none"
    rows = ["trajectory,angle,velocity"] + [f"t{k},{a:.2f},{(1 + a) * (1 + k / 10):.3f}"
                                            for k in range(6) for a in (0.5, 1.0, 1.5, 2.0)]
    data = tmp_path / "no-distance.csv"
    data.write_text("\n".join(rows) + "\n")
    result = rlff("fit", str(data), "-o", str(tmp_path / "m.json"))
    assert result.code == 2
    line = result.stderr.strip().splitlines()[-1]
    assert line.startswith(f"rlff: error: {data}: no column 'distance', the basket distance each throw aimed at (m)")
    assert "rlff data import RECORDINGS --manifest baskets.csv" in line and "add a distance column" in line
    assert not (tmp_path / "m.json").exists()
    # named inputs still fit a model without context, on purpose
    chosen = rlff("fit", str(data), "-o", str(tmp_path / "m.json"), "--inputs", "angle", "-k", "1", "--json")
    assert chosen.code == 0, chosen.stderr
    assert json.loads(chosen.stdout)["inputs"] == ["angle"]


def test_fit_warns_for_throws_not_cut_to_one_sweep_and_not_for_cleaned_ones(thesis_files, rlff, tmp_path):
    # imported throws hold their wind-up and follow-through: a model fitted on them took them
    # silently, and generated a 64 s throw peaking at 1.2 rad/s from real MSR recordings
    cleaned, _, _ = thesis_files
    quiet = rlff("fit", str(cleaned), "-o", str(tmp_path / "clean.json"), "-k", "2")
    assert quiet.code == 0 and "not cut" not in quiet.stderr, quiet.stderr
    frame = pd.read_csv(cleaned)
    first = frame["trajectory"].iloc[0]
    rows = frame.index[frame["trajectory"] == first]
    wound = frame.copy()
    wound.loc[rows[3], "angle"] = wound.loc[rows[1], "angle"]  # goes back at its fourth sample
    data = tmp_path / "uncut.csv"
    wound.to_csv(data, index=False)
    result = rlff("fit", str(data), "-o", str(tmp_path / "m.json"), "-k", "2")
    assert result.code == 0, result.stderr
    assert (f"warning: {data}: 1 of {frame['trajectory'].nunique()} throws are not cut to the elbow's one sweep "
            f"up to the release (their angle goes back; the first, '{first}', at sample 3)") in result.stderr
    assert f"rlff data preprocess {data} --preset thesis -o clean.csv" in result.stderr


def test_lengths_in_millimetres_are_asked_about_as_millimetres(rlff, tmp_path):
    # 1750 was asked about centimetres alone (17.5 m) where 1.75 m in millimetres is likelier;
    # distances of 750 to 2750 and a pedestal of 50 got no hint at all (until 2026-12-07)
    from rlff.errors import InputError
    from rlff.limits import check_distance, check_pedestal

    for value, units in ((1750, "centimetres or millimetres"), (175, "centimetres"), (4500, "millimetres")):
        with pytest.raises(InputError, match=rf"\({units}\? the distance is in metres\)$"):
            check_distance("--basket", value)
    with pytest.raises(InputError, match=r"\(centimetres or millimetres\? the height is in metres\)$"):
        check_pedestal(50, "--pedestal")
    data = _demos_in_other_units(tmp_path / "mm.csv", (750, 1500, 2750), per_metre=1000)
    result = rlff("fit", str(data), "-o", str(tmp_path / "m.json"))
    assert result.code == 2
    assert "holds 750 to 2750, outside the basket distances 0.3 to 20 m (millimetres? the distance is in metres)" \
        in result.stderr


def _synth_throws(rlff, path, *extra: str) -> pd.DataFrame:
    """Simulated recordings (``rlff data synth throws``) written to ``path``, read back as a frame."""
    made = rlff("data", "synth", "throws", "-o", str(path), "--subjects", "1", "--throws", "2", *extra)
    assert made.code == 0, made.stderr
    return pd.read_csv(path)


def test_fit_refuses_a_velocity_in_degrees_per_second(rlff, tmp_path):
    # fitted without a word; generate then wrote a throw of 3 ms peaking at 688 "rad/s"
    frame = _synth_throws(rlff, tmp_path / "demos.csv")
    frame["velocity"] *= 180 / np.pi
    data = tmp_path / "deg.csv"
    frame.to_csv(data, index=False)
    result = rlff("fit", str(data), "-o", str(tmp_path / "m.json"))
    assert result.code == 2
    assert re.fullmatch(rf"rlff: error: {re.escape(str(data))}: column 'velocity' integrates over the throws' time "
                        r"column to a median 5\d\.?\d* times their angle's change \(along the throw, back and forth\): .* \(degrees per second\? velocity "
                        r"is in rad/s\)\n", result.stderr), result.stderr
    assert not (tmp_path / "m.json").exists()
    untimed = tmp_path / "untimed.csv"
    frame.drop(columns=["time"]).to_csv(untimed, index=False)
    result = rlff("fit", str(untimed), "-o", str(tmp_path / "m.json"))
    assert result.code == 2
    assert f"{untimed}: column 'velocity' peaks at " in result.stderr and "degrees per second?" in result.stderr


def test_fit_says_what_it_could_not_check_of_a_file_without_time(thesis_files, rlff, tmp_path):
    data, _, _ = thesis_files
    result = rlff("fit", str(data), "-o", str(tmp_path / "m.json"), "-k", "1")
    assert result.code == 0, result.stderr
    assert (f"note: {data}: no time column: column 'velocity' checked against a person's fastest joint (60 rad/s) "
            "only, not against the rate at which the position changes") in result.stderr
    _synth_throws(rlff, tmp_path / "timed.csv")
    timed = rlff("fit", str(tmp_path / "timed.csv"), "-o", str(tmp_path / "t.json"), "-k", "1")
    assert timed.code == 0, timed.stderr
    assert "checked against a person's fastest joint" not in timed.stderr


def test_generate_warns_where_most_of_the_path_is_no_throw(rlff, tmp_path):
    # a model of uncut recordings (wind-up and follow-through) gave a path 63-100 % at velocity
    # <= 0, said only in a note that -q dropped
    _synth_throws(rlff, tmp_path / "raw.csv")
    assert rlff("fit", str(tmp_path / "raw.csv"), "-o", str(tmp_path / "m.json"), "-k", "3").code == 0
    result = rlff("-q", "generate", str(tmp_path / "m.json"), "-c", "distance=2", "-o", str(tmp_path / "t.csv"),
                  "--json")
    assert result.code == 0, result.stderr
    warning = ("100 of 100 points have velocity <= 0 along the path: most of it is no throw (the arm rests there); a "
               "model of demonstrations not cut to one throw up to the release gives such paths: clean them (rlff data "
               "preprocess DEMOS --preset thesis) and fit again")
    assert f"warning: {warning}" in result.stderr
    assert warning in json.loads(result.stdout)["warnings"]


def test_generate_keeps_a_few_points_at_rest_a_note(thesis_files, rlff, tmp_path):
    _, model, _ = thesis_files
    result = rlff("generate", str(model), "-c", "distance=8.5", "-o", str(tmp_path / "t.csv"))
    assert result.code == 0, result.stderr
    assert "most of it is no throw" not in result.stderr


@pytest.mark.parametrize("name", ["model.csv", "model.parquet", "model.jsonl", "model.TXT"])
def test_a_model_named_as_another_kind_of_file_is_refused(thesis_files, rlff, tmp_path, name):
    # rlff fit -o model.csv wrote JSON into model.csv without a word
    data, _, _ = thesis_files
    out = tmp_path / name
    result = rlff("fit", str(data), "-o", str(out))
    assert result.code == 2 and len(result.stderr.strip().splitlines()) == 1, result.stderr
    assert (f"-o/--output {out}: rlff fit writes a model, which is JSON, where the suffix {out.suffix} names another "
            f"kind of file: name it .json ({out.with_suffix('.json')})") in result.stderr
    assert not out.exists()
