"""The invariance property of ``test_invariance.py`` for embrace angles of 230 to 300 degrees
(rings, the costliest cases), run beside the other parts."""
from hypothesis import example, given, settings, strategies as st

from test_invariance import EXAMPLES, OTHERS, SETTINGS, check_invariance


@settings(SETTINGS, max_examples=EXAMPLES - EXAMPLES // 2)
@given(beta=st.floats(230.0, 300.0), **OTHERS)
@example(beta=246.99331510740546, t_over_r=0.9945264899670817, n=29, log_r=3.0, log_rho=0.0)
@example(beta=300.0, t_over_r=0.03, n=7, log_r=0.0, log_rho=1.0)     # t_min's regula falsi: 2.4e-9 apart
@example(beta=268.5381491363777, t_over_r=0.9878847104445414, n=126, log_r=0.0, log_rho=0.0)
def test_units_and_mirror_do_not_change_the_answer_ring(beta, t_over_r, n, log_r, log_rho):
    check_invariance(beta, t_over_r, n, log_r, log_rho)
