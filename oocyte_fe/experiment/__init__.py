"""FE experiments on a layered cell as data: a description, one driver, a result."""

from oocyte_fe.experiment.description import Experiment
from oocyte_fe.experiment.driver import ExperimentResult, run_experiment

__all__ = ["Experiment", "ExperimentResult", "run_experiment"]
