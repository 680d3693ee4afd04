"""The settings of the paper's nose-gear analyses (:mod:`.nose_gear`), shared with their figures
(:mod:`._nose_gear_figures`): parameter ranges and the rates of the slow time simulations."""

L_SP1_RANGE = (-0.175, 0.175)  # m: the attachment anywhere on lock link 1 (L4 = 0.35 m)
LU_RANGE = (1.25, 1.35)  # m: unstrained spring lengths of Fig. 11 and the design region
FIG7_RATE, FIG7_DAMPING = 20.0, 5.0  # N/s and 1/s of the Fig. 7 time simulation
DOWNLOCK_RATE, DOWNLOCK_DAMPING = 2.0, 20.0  # N/s and 1/s of the slow downlock ramp
MISRIG = -0.0005  # m: lock-link lug short of the aligned position (Fig. 8 variant)
