"""rlff: robot learning from failed demonstrations.

Fit a Gaussian Mixture Model to (joint angle, basket distance, joint velocity) samples, condition
it on the angle and the distance (Gaussian Mixture Regression), turn every conditional Gaussian
into a donut (Donut Mixture Model) and take, for every angle, the velocity of highest density.

The chain in Python, a stage a line (docs/*.md for each)::

    from rlff import Model
    from rlff.formats import read_dataset                # recordings: rlff.capture.import_recordings
    from rlff.preprocess import Pipeline
    from rlff.robot import RobotMapping, load_robot
    from rlff.robot.plan import plan
    from rlff.sim import simulate_throw

    demos = read_dataset("demos.csv")                    # angle (rad), distance (m), velocity (rad/s)
    clean, report = Pipeline.preset("thesis").run(demos)
    model = Model.fit(clean)                             # K by BIC
    path = model.generate({"distance": 1.4})             # the DMM's throw for a 1.4 m basket
    robot = load_robot()                                 # the built-in Comau Smart5 SiX
    trajectory = plan(RobotMapping.for_robot(robot), path.angle, path.velocity).trajectory
    outcome = simulate_throw(trajectory, 1.4, robot=robot)   # .hit, .miss (m)

and ``rlff.learn.learn`` closes the loop until the ball is in. The public names below are
imported lazily so that ``import rlff`` stays cheap for the command line.
"""

from __future__ import annotations

from rlff._lazy import lazy_exports

__version__ = "0.1.0"

# public name -> module that defines it
_EXPORTS = {
    "RlffError": "rlff.errors",
    "InputError": "rlff.errors",
    "GaussianMixture": "rlff.model.mixture",
    "select_components": "rlff.model.mixture",
    "condition": "rlff.model.regression",
    "predict": "rlff.model.regression",
    "Conditional": "rlff.model.regression",
    "donut_pdf": "rlff.model.donut",
    "dmm_pdf": "rlff.model.donut",
    "dmm_mode": "rlff.model.donut",
    "exploration_factor": "rlff.model.donut",
    "DonutMode": "rlff.model.donut",
    "Model": "rlff.model.model",
    "GeneratedPath": "rlff.model.model",
    "Dataset": "rlff.dataset",
    "Trajectory": "rlff.dataset",
}

__all__ = sorted(_EXPORTS) + ["__version__"]


__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS)
