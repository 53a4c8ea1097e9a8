"""The metrics of the case kind ``microchannel_vof``: name -> what it measures."""

METRICS = {
    "ratio_at_junction": "axis ratio b/a when the centroid crosses x = 0, per pressure",
    "ratio_end": "axis ratio b/a at the end of the run, per pressure",
    "mean_error_experiment_pct": "mean |ratio_at_junction / experiment - 1| over the run, %",
    "mean_error_paper_vof_pct": "mean |ratio_at_junction / paper VOF - 1|, %",
    "kelvin_voigt_mean_error_pct": "reduced model against the experiment, same pressures, %",
    "max_volume_error": "largest |relative volume change| of the ZP and cytoplasm phases",
    "mesh_change_pct": "ratio change between the two meshes at x = 0 (else at the end), %",
    "cap_change_pct": "ratio change between the two caps at x = 0 (else at the end), %",
    "seconds_per_ms": "wall seconds per simulated ms (first pressure, one run)",
    "dt_change_pct": "change of 1 - b/a at x = 0 from dt to dt/2 (first pressure), %",
    "dt_change_max_pct": "largest change of 1 - b/a between successive dt halvings, %",
    "mesh_deformation_change_pct": "change of 1 - b/a at x = 0 between the two meshes, %",
    "zp_change_pct": "change of 1 - b/a at x = 0, the ZP's curve for the whole cell, %",
    "beside_ratio_at_junction": "the beside model's b/a at x = 0, per beside pressure",
    "beside_mean_error_experiment_pct": "the beside model against the experiment, mean %",
    "beside_dt_change_pct": "the beside model: change of 1 - b/a from dt to dt/2, %",
    "traction_imbalance_pct": "|net traction force - cell momentum rate| / load on the cell, %",
    "traction_force_x": "net traction force on the cell per unit depth, x (nN/um)",
    "traction_force_y": "net traction force on the cell per unit depth, y (nN/um)",
    "traction_at_x_um": "centroid x of the written time the traction is taken at (um)",
    "cv_imbalance_pct": "momentum budget of a box around the cell: |miss| / load on its faces, %",
    "diffuse_imbalance_pct": "the cell's momentum rate against the force of its diffuse "
    "interface, -sum sigma . grad(alpha) dA: |miss| / load on the band, %",
    "diffuse_explicit_imbalance_pct": "the same with the transposed part of the viscous stress "
    "at the first step's velocity (the solver's explicit term), %",
    "diffuse_scheme_imbalance_pct": "the same with the remainder of the solver's upwind-biased "
    "convection on the lattice (zero in the continuum; vof.convection), %",
    "elastic_cell_b_over_a": "b/a of the AFM-elastic FE cell under the traction, per pressure",
    "elastic_min_stretch": "the smallest principal stretch in the AFM-elastic FE cell, per "
    "pressure (below 0.65 a compressed neo-Hookean surface creases)",
    "elastic_mae": "AFM-elastic cell: mean |b/a - experiment| over the pressures",
    "elastic_follower_b_over_a": "b/a of the AFM-elastic cell under the traction's normal part "
    "as a follower pressure, per pressure",
    "elastic_follower_min_stretch": "the smallest principal stretch in the cell under the "
    "follower reading, per pressure",
    "elastic_follower_mae": "AFM-elastic cell, follower reading: mean |b/a - experiment|",
    "recompute_b_over_a": "deform-recompute: the elastic cell's b/a in each pass (first pressure)",
    "recompute_last_change_pct": "deform-recompute: change of b/a in the last carried pass, %",
    "recompute_shape_b_over_a": "deform-recompute: b/a of the FE's outline at x = 0 in each "
    "pass (the shape the next pass starts from before under-relaxation; first pressure)",
    "recompute_final_b_over_a": "deform-recompute at every pressure (recompute_pressures = "
    "'all'): the last carried pass's b/a where the passes converged, per pressure",
    "recompute_final_shape_b_over_a": "deform-recompute at every pressure: the last carried "
    "pass's FE outline at x = 0, b/a, where the passes converged, per pressure",
    "recompute_passes_run": "deform-recompute at every pressure: the passes run, per pressure",
    "liquid_mae": "liquid cell (VOF): mean |b/a - experiment| over the pressures",
    "paper_vof_mae": "paper's VOF: mean |b/a - experiment| over the same pressures",
    "dt_order": "observed order in dt of b/a at x = 0 (dt, dt/2, dt/4; nan: not monotone)",
    "dt_factor": "ratio of successive differences of b/a over dt, dt/2, dt/4 (< 0: alternating)",
    "ratio_dt_limit": "b/a at x = 0 extrapolated to dt -> 0 (Richardson, first pressure)",
    "deformation_dt_limit": "1 - b/a at x = 0 extrapolated to dt -> 0 (first pressure)",
    "ratio_dt_error_pct": "b/a at x = 0 with the case's dt against its dt -> 0 limit, %",
    "elastic_mesh_change_pct": "AFM-elastic cell: b/a under the second mesh's flow against the "
    "first's (first pressure), %",
    "elastic_mesh_b_over_a": "AFM-elastic cell: b/a under each finer mesh's flow (first pressure)",
    "elastic_follower_mesh_b_over_a": "AFM-elastic cell, follower reading: b/a under each finer "
    "mesh's flow (first pressure)",
    "elastic_mesh_limit_b_over_a": "AFM-elastic cell: h -> 0 limit of b/a (power law through the "
    "finest three flow meshes, first pressure; nan: no order)",
    "elastic_follower_mesh_limit_b_over_a": "AFM-elastic cell, follower reading: h -> 0 limit of "
    "b/a (finest three flow meshes, first pressure)",
    "mesh_dx_um": "mesh study: the cell sizes, the case's mesh first (um)",
    "mesh_deformation": "mesh study: 1 - b/a at x = 0 on each mesh (first pressure)",
    "mesh_order": "mesh study: observed order p of e(h) = e0 + C h^p (finest three meshes)",
    "deformation_mesh_limit": "mesh study: 1 - b/a extrapolated to h -> 0 (first pressure)",
    "deformation_mesh_error_pct": "mesh study: the case's 1 - b/a against its h -> 0 limit, %",
    "converged_b_over_a": "Table 4 from the mesh limits: b/a of each pressure's h -> 0 limit "
    "(nan: no order)",
    "converged_order": "Table 4 from the mesh limits: each pressure's observed order in h",
    "converged_mean_error_experiment_pct": "the limits' mean |b/a / experiment - 1|, %",
    "converged_liquid_mae": "the limits' mean |b/a - experiment|",
    "max_courant": "largest Courant number over every run of the case (the solvers' logs)",
    "max_courant_read": "largest Courant number of any run until its cell passes x = +25 um "
    "(the last state b/a at x = 0 is read from; checked)",
    "max_interface_courant": "largest interface Courant number over every run",
}
