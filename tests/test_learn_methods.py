"""A method of one's own: a subclass of rlff.learn.Method given to learn() and to the learning
benchmark as the class itself. Real model, real MuJoCo, real loky workers."""

from __future__ import annotations

import json
import re
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from rlff.dataset import Dataset
from rlff.errors import InputError
from rlff.learn import Method, Proposal, learn, scale_speed

DOCS = Path(__file__).resolve().parents[1] / "docs" / "learn.md"


@pytest.fixture(scope="module")
def demos() -> Dataset:
    from rlff.preprocess import Pipeline
    from rlff.synthetic.throws import simulate_throws

    raw = simulate_throws(3, subjects=3, distances=(1.0, 1.25, 1.5), throws_per_distance=2, all_short=True)
    clean, _ = Pipeline.preset("thesis").run(raw)
    return clean


class Slower(Method):
    """The demonstrations' mean throw for the basket, 5 % slower after each miss."""

    name = "slower"
    feedbacks = ("binary", "distance")

    def __init__(self, problem):
        super().__init__(problem)
        path = problem.demonstrations_model().generate({"distance": problem.target}, problem.angles, exploration=0.0)
        self.mean = Proposal.of_outputs(path.angle, path.gmr_means, path.output_names, problem.target)

    def propose(self, history):
        factor = 0.95 ** len(history)
        return replace(scale_speed(self.mean, factor), info={"factor": factor})


def test_the_example_of_the_docs_runs_as_written(capsys):
    text = DOCS.read_text()
    section = text[text.index("## Writing your own method"):]
    code = re.search(r"```python\n(.*?)```", section, re.DOTALL).group(1)
    exec(compile(code, f"{DOCS}, Writing your own method", "exec"), {"__name__": "docs_example"})
    attempts, hit, misses = capsys.readouterr().out.split(maxsplit=2)
    assert 1 <= int(attempts) <= 4 and hit in ("True", "False") and misses.startswith("[")


def test_a_method_class_learns_is_logged_by_its_name_and_resumes(demos, tmp_path):
    log = tmp_path / "slower.jsonl"
    first = learn(demos, 1.4, update=Slower, budget=2, log_path=log)
    assert first.update == "slower" and first.attempts == 2
    assert json.loads(log.read_text().splitlines()[0])["run"]["update"] == "slower"
    assert json.loads(log.read_text().splitlines()[0])["budget"] == 2
    assert [a.info["factor"] for a in first.history] == pytest.approx([1.0, 0.95])
    again = learn(demos, 1.4, update=Slower, budget=3, log_path=log)
    assert again.resumed == 2 and again.history[-1].info["factor"] == pytest.approx(0.95 ** 2)
    assert json.loads(log.read_text().splitlines()[0])["budget"] == 3  # the budget its last attempt had
    with pytest.raises(InputError, match=r"update = 'slower' in the log.*'calibrate'"):
        learn(demos, 1.4, budget=4, log_path=log)


class Nameless(Slower):
    name = ""


class Impostor(Slower):
    name = "secant"


class Deaf(Slower):
    feedbacks = ("vision",)


@pytest.mark.parametrize(("update", "words"), [
    (Slower.propose, r"update must be a method's name \(failure, .*\) or a subclass of rlff.learn.Method, got"),
    (Nameless, r"method Nameless has no name: set its class attribute name"),
    (Impostor, r"method Impostor is named 'secant', as a built-in method is: give it a name of its own"),
    (Deaf, r"method Deaf has feedbacks \('vision',\): a tuple of 'binary' and 'distance'"),
    (Method, r"method Method has no name"),
    (type("Abstract", (Method,), {"name": "abstract"}), r"method Abstract has no propose\(history\)"),
])
def test_what_is_no_method_is_refused_saying_what_a_method_needs(demos, update, words):
    with pytest.raises(InputError, match=words):
        learn(demos, 1.4, update=update, budget=1)


@pytest.mark.slow
def test_the_benchmark_runs_a_method_class_in_its_workers():
    # the only route had been to insert it into rlff.learn.METHODS, which loky's workers never see
    from rlff.learn.benchmark import learning_benchmark
    from rlff.learn.scenarios import Feedback, Scenario

    scenario = Scenario("short", feedbacks=(Feedback("binary", "binary"),), baskets=(1.4,))
    runs = learning_benchmark(scenario, seeds=1, methods={"binary": (Slower, "imitation")}, jobs=2, budget=2)
    assert [run.method for run in runs] == ["slower", "imitation"]
    assert all(1 <= run.attempts <= 2 for run in runs)


@pytest.mark.slow
def test_the_benchmark_runs_only_the_feedback_kinds_its_methods_name():
    # the docs' example, {"distance": (Faster, "secant")}, ended the default scenario, which also
    # runs binary feedback, with KeyError: 'binary'
    from rlff.learn.benchmark import learning_benchmark
    from rlff.learn.scenarios import Scenario

    runs = learning_benchmark(Scenario("short", baskets=(1.4,)), seeds=1, methods={"distance": (Slower, "secant")},
                              jobs=1, budget=2)
    assert [(run.feedback, run.method) for run in runs] == [("distance", "slower"), ("distance", "secant")]


class Careless(Slower):
    """Proposes what its class attribute ``proposal`` makes of the mean throw."""

    name = "careless"
    proposal = staticmethod(lambda mean: mean)

    def propose(self, history):
        return type(self).proposal(self.mean)


def with_value(column: str, sample: int, value: float):
    """What ``Careless`` proposes: the mean throw with ``column`` at ``sample`` set to ``value``."""
    def proposal(mean):
        values = getattr(mean, column).copy()
        values[sample] = value
        return replace(mean, **{column: values})
    return proposal


#: The angle grid of the run at 1.4 m of ``demos`` (rad): its first and last angle, as messages print them.
GRID = r"from 0.7498 to 1.515 rad"


@pytest.mark.parametrize(("proposal", "words"), [
    # an AttributeError ('dict' object has no attribute 'path'), then a NaN named by sample alone
    (lambda mean: {"angle": mean.angle, "velocity": mean.velocity},
     r"^attempt 1: careless's propose returned dict .*: it must return an rlff.learn.Proposal \(angle and velocity, "
     r"arrays of shape \(T,\) in rad and rad/s, T = 30: angle is problem.angles\)$"),
    (with_value("velocity", 5, np.nan), r"^attempt 1: the throw careless proposed: velocity at sample 5 is nan \(1 of "
                                        r"30 not finite\): every value of a proposal must be a finite number$"),
    (with_value("angle", 7, np.inf), r"^attempt 1: the throw careless proposed: angle at sample 7 is inf"),
    # the planner's "angle and velocity must be 1-D of one length", which said nothing of the grid
    (lambda mean: replace(mean, velocity=mean.velocity[:-3]), r"^attempt 1: the throw careless proposed: velocity "
                                                             r"of shape \(27,\), where problem.angles, the angle "
                                                             rf"grid every throw follows, has shape \(30,\), {GRID}"),
    # the rest were thrown as they came: a swing from the release back to its start, 2.5 m short
    (lambda mean: replace(mean, angle=mean.angle[::-1].copy(), velocity=mean.velocity[::-1].copy()),
     r"^attempt 1: the throw careless proposed: angle runs from 1.515 to 0.7498 rad, the grid reversed: "
     rf"problem.angles runs {GRID}, the release last; give the throw in the grid's order$"),
    # ... a throw let go where the demonstrations do not
    (lambda mean: replace(mean, angle=mean.angle[:-10], velocity=mean.velocity[:-10]),
     r"^attempt 1: the throw careless proposed: angle of shape \(20,\), velocity of shape \(20,\), where "
     rf"problem.angles, the angle grid every throw follows, has shape \(30,\), {GRID}: give every column a value "
     r"at each angle of the grid$"),
    (lambda mean: replace(mean, angle=mean.angle[:, None], velocity=mean.velocity[:, None]),
     r"^attempt 1: the throw careless proposed: angle of shape \(30, 1\), velocity of shape \(30, 1\), where"),
    (with_value("angle", 12, 1.2), r"^attempt 1: the throw careless proposed: angle at sample 12 is 1.2 rad, where "
                                   rf"problem.angles has 1.06646 rad \({GRID}, 30 samples\): give the throw at the "
                                   r"grid's angles$"),
    # ... and a shoulder this one-joint run does not drive
    (lambda mean: replace(mean, arm={"shoulder": np.full(mean.angle.size, 2.5),
                                     "shoulder_velocity": np.zeros(mean.angle.size)}),
     r"^attempt 1: the throw careless proposed: its arm holds shoulder, shoulder_velocity; this run's throw drives "
     r"one joint, the elbow's angle and velocity alone: leave arm empty \(its default\)$"),
])
def test_a_proposal_off_the_grid_or_that_cannot_be_thrown_is_refused_naming_the_method_and_the_attempt(
        demos, tmp_path, proposal, words):
    careless = type("Careless", (Careless,), {"proposal": staticmethod(proposal)})
    log = tmp_path / "careless.jsonl"
    with pytest.raises(InputError, match=words):
        learn(demos, 1.4, update=careless, budget=2, log_path=log)
    assert not log.exists()  # nothing logged: a run that logs no attempt leaves no log


def test_a_proposal_on_the_grid_within_its_round_off_is_thrown(demos):
    # the grid as float32 (about 1e-7 rad off), and a hair beside it: the same throw
    for shifted in (lambda mean: mean.angle.astype(np.float32),
                    lambda mean: mean.angle + 1e-4 * (mean.angle[1] - mean.angle[0])):
        careless = type("Careless", (Careless,), {"proposal": staticmethod(
            lambda mean, shifted=shifted: replace(mean, angle=shifted(mean)))})
        assert learn(demos, 1.4, update=careless, budget=1).attempts == 1


class Throws(Slower):
    """The mean throw; counts the throws its executor makes (``thrown``)."""

    name = "counted"


@pytest.mark.parametrize(("field", "value", "words"), [
    # an array in info had failed the log's write after the arm had thrown: thrown, not recorded
    ("info", {"step": np.arange(2)}, r"^attempt 2: the throw counted proposed: its info\['step'\] is ndarray "
                                     r"array\(\[0, 1\]\), which the attempts log cannot keep as JSON"),
    ("info", {"spread": float("nan")}, r"its info\['spread'\] is float nan, which the attempts log cannot keep"),
    ("info", [1, 2], r"its info is list \[1, 2\]: give a dict"),
    ("exploration", np.ones(3), r"its exploration is ndarray array\(\[1., 1., 1.\]\): give one number"),
    ("query", "1.4", r"its query is str '1.4': give one number, a distance in m, NaN when no model was queried"),
    ("query", np.inf, r"its query is float inf: give one number"),
])
def test_what_a_proposal_says_of_itself_is_checked_before_the_arm_throws(demos, tmp_path, field, value, words):
    thrown = []

    class Careless(Throws):
        def propose(self, history):
            mean = super().propose(history)
            return replace(mean, **{field: value}) if history else mean

    def executor(trajectory):
        from rlff.sim import simulate_throw

        thrown.append(trajectory)
        return simulate_throw(trajectory, 1.4)

    log = tmp_path / "careless.jsonl"
    with pytest.raises(InputError, match=words):
        learn(demos, 1.4, update=Careless, budget=3, log_path=log, executor=executor)
    assert len(thrown) == 1  # the second throw was refused before the arm threw it
    assert len(log.read_text().splitlines()) == 2  # ... and the log keeps the first: header and attempt 1


def test_a_methods_own_error_names_the_attempt_and_the_method(demos):
    class Buggy(Throws):
        name = "buggy"

        def propose(self, history):
            if history:
                raise ValueError("my bug")
            return super().propose(history)

    with pytest.raises(ValueError, match="my bug") as raised:
        learn(demos, 1.4, update=Buggy, budget=3)
    assert raised.value.__notes__ == ["raised by buggy's propose at attempt 2"]


@pytest.mark.parametrize(("proposal", "words"), [
    (lambda mean: replace(mean, velocity=-mean.velocity),
     r"^attempts 1-2: the throw careless proposed was changed before it was thrown \(at attempt 1\): its velocity "
     rf"runs against problem.angles' direction \({GRID}\) at 30 of 30 samples, the release among them: the path "
     r"was thrown as a crawl at 0.1 rad/s"),
    # at rest at its start, against the grid after: no sample moves forward, so a crawl too (it
    # had been said to be thrown at rest, as if another sample had moved forward)
    (lambda mean: replace(mean, velocity=np.concatenate([[0.0], -mean.velocity[1:]])),
     r"^attempts 1-2: .* at 29 of 30 samples, the release among them: the path was thrown as a crawl at 0.1 "
     r"rad/s, the ball let go at that; check the velocity's sign$"),
    (lambda mean: replace(mean, velocity=np.concatenate([mean.velocity[:-3], -mean.velocity[-3:]])),
     r"^attempts 1-2: .* at 3 of 30 samples, the release among them: those were thrown at rest, so the ball left "
     r"the hand standing still; check the velocity's sign$"),
    (lambda mean: replace(mean, velocity=np.degrees(mean.velocity)),
     r"^attempts 1-2: .*: it asks for a release at [0-9.]+ rad/s, [0-9]+ times the fastest the arm makes "
     r"\(problem.max_speed, [0-9.]+ rad/s\): saturated at the arm's limit; velocities in deg/s\? Give rad/s$"),
])
def test_a_throw_the_loop_changes_before_throwing_it_is_said(demos, proposal, words):
    # each had been thrown without a word: a crawl, a release at rest, every sample saturated
    careless = type("Careless", (Careless,), {"proposal": staticmethod(proposal)})
    result = learn(demos, 1.4, update=careless, budget=2)
    assert any(re.match(words, note) for note in result.notes), result.notes


def test_the_mean_throw_is_not_said_to_be_changed(demos):
    assert learn(demos, 1.4, update=Careless, budget=2).notes == []


class Backwards(Careless):
    """Proposes the mean throw with the grid reversed (a swing from the release back to its start)."""

    name = "backwards"
    proposal = staticmethod(lambda mean: replace(mean, angle=mean.angle[::-1].copy(),
                                                 velocity=mean.velocity[::-1].copy()))


def test_the_benchmark_refuses_a_proposal_off_the_grid_as_the_loop_does():
    # the benchmark's runs are the loop's (learn), so their proposals pass the same check
    from rlff.learn.benchmark import learning_benchmark
    from rlff.learn.scenarios import Feedback, Scenario

    scenario = Scenario("short", feedbacks=(Feedback("binary", "binary"),), baskets=(1.4,))
    with pytest.raises(InputError, match=r"^short, landings none, seed 100, basket 1.4 m, binary feedback, backwards: "
                                         r"attempt 1: the throw backwards proposed: angle runs from .* rad, the grid "
                                         r"reversed: problem.angles runs from .* rad, the release last; give the "
                                         r"throw in the grid's order$"):
        learning_benchmark(scenario, seeds=1, methods={"binary": (Backwards,)}, jobs=1, budget=2)


class Seeing(Slower):
    """Slower, keeping the last problem it was given in ``seen``."""

    name = "seeing"
    seen: list = []

    def __init__(self, problem):
        super().__init__(problem)
        type(self).seen[:] = [problem]


def test_a_result_and_a_problem_print_one_short_line_not_their_arrays(demos):
    # the dataclasses printed every attempt's arrays (4.5 kB) and a partial holding the robot
    # mapping (3.6 kB)
    result = learn(demos, 1.4, update=Seeing, budget=2, feedback="distance")
    misses = ", ".join(f"{miss:.3f}" for miss in result.misses)
    assert repr(result) == (f"LearningResult(hit={result.hit}, attempts={result.attempts}, misses=[{misses}], "
                            "target=1.4, feedback='distance', update='seeing')")
    problem = Seeing.seen[0]
    assert repr(problem) == (f"Problem(target=1.4, feedback='distance', T={problem.angles.size}, "
                             f"max_speed={problem.max_speed:.4g}, outputs=('velocity',))")
    assert len(repr(result)) < 200 and len(repr(problem)) < 120


@pytest.fixture
def own_module(tmp_path, monkeypatch):
    """The name of a module of one's own (tests/own_method.py) in the current folder, a new one,
    with ``sys.path`` and ``sys.modules`` as they were afterwards."""
    import sys

    from own_method import write_module

    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(sys, "path", [entry for entry in sys.path if entry not in ("", str(tmp_path))])
    name = write_module(tmp_path)
    yield name
    sys.modules.pop(name, None)


def test_a_method_named_module_colon_class_is_imported_from_the_current_folder(own_module):
    from rlff.learn.loop import method_of

    method = method_of(f"{own_module}:Faster")
    assert method.__name__ == "Faster" and method.name == "faster" and method.__module__ == own_module


@pytest.mark.parametrize(("spec", "words"), [
    ("{m}:Fastr", r"^{m}:Fastr: module {m} \(.*{m}\.py\) has no 'Fastr'; its Method subclasses: Faster$"),
    ("{m}:helper", r"^{m}:helper: helper of {m} is function .*, not a subclass of rlff.learn.Method: give your "
                   r"method's class$"),
    ("{m}:Plain", r"^{m}:Plain: Plain of {m} is type .*, not a subclass of rlff.learn.Method"),
    ("nowhere_at_all:Faster", r"^nowhere_at_all:Faster: no module 'nowhere_at_all' on the Python path \(sys.path\) "
                              r"or in the current folder .*: give MODULE:CLASS of your method's module, e.g. "
                              r"faster:Faster"),
    ("{m}.py:Faster", r"^{m}.py:Faster: MODULE is a module's name, not its file: {m}:Faster$"),
    ("{m}.Faster", r"^unknown update '{m}.Faster' \(known: .*\); a method of your own is MODULE:CLASS, e.g. "
                   r"faster:Faster"),
    ("calibrate:bogus", r"^unknown update 'calibrate:bogus' \(known: "),
])
def test_a_module_colon_class_that_is_no_method_says_what_failed_and_what_to_give(own_module, spec, words):
    from rlff.learn.loop import method_of

    with pytest.raises(InputError, match=words.format(m=own_module)):
        method_of(spec.format(m=own_module))


def test_a_module_that_fails_to_import_is_named_with_its_error(own_module, tmp_path):
    from rlff.learn.loop import method_of

    (tmp_path / f"{own_module}_broken.py").write_text("1 / 0\n")
    with pytest.raises(InputError, match=rf"^{own_module}_broken:Faster: importing {own_module}_broken .*failed: "
                                         r"ZeroDivisionError: division by zero$"):
        method_of(f"{own_module}_broken:Faster")


def test_rlff_learn_runs_a_method_named_module_colon_class_and_resumes_its_log(rlff, demos, own_module, tmp_path):
    from rlff.dataset import write_csv

    write_csv(demos, tmp_path / "demos.csv")
    log = tmp_path / "attempts.jsonl"
    run = ("learn", "demos.csv", "--basket", "1.4", "--log", str(log), "--feedback", "distance", "--update")
    first = rlff(*run, f"{own_module}:Faster", "--budget", "1")
    assert first.code == 0, first.stderr
    assert "update faster)" in first.stdout
    assert json.loads(log.read_text().splitlines()[0])["run"]["update"] == "faster"
    again = rlff(*run, f"{own_module}:Faster", "--budget", "2")
    assert again.code == 0, again.stderr
    assert "resumed 1 attempt from" in again.stderr
    other = rlff(*run, "calibrate", "--budget", "3")
    assert other.code == 2 and ("update = 'faster' in the log, 'calibrate' now, from update (--update)); use another "
                                "log_path (--log), or resume it with --update faster (for a method of your own, MODULE:CLASS of "
                                "the class named 'faster')") in other.stderr
    by_name = rlff(*run, "faster", "--budget", "3")
    assert by_name.code == 2
    assert "unknown update 'faster' (known: " in by_name.stderr
    assert "a method of your own is MODULE:CLASS" in by_name.stderr


@pytest.mark.slow
def test_rlff_bench_learning_runs_a_method_named_module_colon_class_in_its_workers(tmp_path):
    # run as the rlff console script runs (the current folder not on sys.path), with two workers
    import subprocess
    import sys

    from own_method import write_module

    work = tmp_path / "work"
    work.mkdir()
    name = write_module(work)
    entry = tmp_path / "entry.py"
    entry.write_text("import sys\nfrom rlff.cli import main\nsys.exit(main(sys.argv[1:]))\n")
    done = subprocess.run([sys.executable, str(entry), "bench", "learning", "--methods", f"{name}:Faster,imitation",
                           "--feedback", "binary", "--seeds", "1", "--baskets", "1.4", "--budget", "1", "--jobs", "2",
                           "--json"], cwd=work, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    assert {row["method"] for row in json.loads(done.stdout)["rows"]} == {"faster", "imitation"}
