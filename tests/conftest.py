"""Shared set-up of the test suite.

The tests are grouped by what they check: unit/ (one piece against its
definition), verification/ (numbers against analytical solutions, published
tables or a second method), command_line/ (the commands, their outputs and
pictures), robustness/ (bad input, random networks, failures kept on disk)
and mpi/ (several processes). The builders they share (builders.py,
references.py, networks.py, processes.py, admissibility_cases.py) sit here,
beside this file, and are importable from every group.

Tests marked `slow` (`make test-fast` leaves them out: `pytest -m "not slow"`)
are those whose file or own time passed 2 s on the 2-core test machine (pytest
--durations over the whole suite); list a new test here when it is that slow.
"""
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
# the builders here, and each group's folder: a test may take a helper from
# another group's test module (robustness/test_unwritable_output.py from
# command_line/test_resume.py), whichever files a run collects
for folder in [HERE, *sorted(p for p in HERE.iterdir() if p.is_dir() and any(p.glob("test_*.py")))]:
    if str(folder) not in sys.path:
        sys.path.insert(0, str(folder))

import pytest

#: whole files of slow tests (several processes, notebooks, the soaks' subsets)
SLOW_FILES = {
    "tests/mpi/test_mpi.py",
    "tests/command_line/test_notebooks.py",
    "tests/robustness/test_random_networks.py",
    "tests/command_line/test_resume.py",
    "tests/robustness/test_unwritable_output.py",
    "tests/verification/test_injection_kgd.py",
    "tests/verification/test_flow_kgd_viscous.py",
    "tests/verification/test_flow_stimulation_network.py",
    "tests/verification/test_injection_breakdown.py",
    "tests/verification/test_injection_prebreakdown.py",
    "tests/verification/test_injection_quasi_static.py",
    "tests/command_line/test_injection_run.py",
    "tests/command_line/test_pictures_as_steps_finish.py",
}
#: single slow tests, by file and name (every parameter of one)
SLOW_TESTS = {
    "tests/robustness/test_admissibility_property.py::test_check_refuses_or_sif_computes",
    "tests/robustness/test_admissibility_property.py::test_the_console_script_refuses_with_2_or_computes_with_0",
    "tests/command_line/test_cli.py::test_a_slow_step_says_what_it_is_doing",
    "tests/command_line/test_cli.py::test_check_accepts_every_shipped_case",
    "tests/command_line/test_cli.py::test_invalid_case_exits_2_with_one_line",
    "tests/verification/test_contact_kkt.py::test_cycling_active_set_falls_back_to_an_exact_solve",
    "tests/verification/test_contact_kkt.py::test_kkt_and_initial_guess",
    "tests/verification/test_far_field_run.py::test_a_fixed_mesh_run_reuses_the_far_field_and_gives_the_whole_factorisations_answers",
    "tests/verification/test_far_field_run.py::test_a_resumed_fixed_mesh_run_ends_on_the_uninterrupted_runs_geometry",
    "tests/command_line/test_friction_run.py::test_a_killed_coulomb_run_resumes_to_the_same_geometry_and_slip",
    "tests/verification/test_growth_propagation.py::test_a_join_connects_the_pressures",
    "tests/verification/test_growth_propagation.py::test_a_wing_joins_another_fracture_as_a_t",
    "tests/verification/test_growth_sif_method.py::test_the_command_line_says_it_once",
    "tests/verification/test_growth_symmetry.py::test_wings_mirror_through_the_centre",
    "tests/verification/test_growth_to_rim.py::test_the_disc_wings_run_to_the_load_points",
    "tests/unit/test_meshing_junctions.py::test_a_hanging_gmsh_is_retried_once_then_fails",
    "tests/unit/test_mid_nodes.py::test_first_mesh_of_each_case",
    "tests/unit/test_pair_saddle.py::test_a_run_through_the_saddle_route_grows_as_the_dense_one",
    "tests/unit/test_pair_saddle.py::test_a_set_near_the_factorised_one_is_solved_by_an_update_as_by_a_new_factorisation",
    "tests/unit/test_pair_saddle.py::test_the_saddle_route_is_the_dense_one",
    "tests/unit/test_picture_worker.py::test_a_failed_run_draws_its_finished_steps_in_the_worker",
    "tests/unit/test_picture_worker.py::test_run_draws_in_the_worker_every_picture_drawn_here",
    "tests/command_line/test_plot.py::test_pvd_lists_exactly_the_step_files_with_increasing_times",
    "tests/verification/test_pressure_connection.py::test_the_join_floods_the_dry_fractures",
    "tests/verification/test_sif_edge_crack.py::test_strain_energy_converges_linearly",
    "tests/robustness/test_sif_warnings.py::test_the_closed_fractures_under_friction_warn_no_more",
}


def pytest_configure(config):
    config.addinivalue_line("markers", "slow: takes more than ~2 s; `make test-fast` skips it")


def pytest_collection_modifyitems(config, items):
    named = set()
    for item in items:
        path = item.nodeid.split("::")[0]
        test = item.nodeid.split("[")[0]
        if path in SLOW_FILES or test in SLOW_TESTS:
            item.add_marker(pytest.mark.slow)
            named.add(path if path in SLOW_FILES else test)
    # a renamed or removed test must leave these lists too: over the whole
    # suite every entry names something collected
    if [str(a) for a in config.args] == ["tests"] and not config.option.keyword:
        unknown = (SLOW_FILES | SLOW_TESTS) - named
        if unknown:
            raise pytest.UsageError(f"tests/conftest.py marks as slow what is not collected: {sorted(unknown)}")
