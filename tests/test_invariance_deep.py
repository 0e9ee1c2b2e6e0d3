"""The invariance property of ``test_invariance.py`` for embrace angles of 160 to 230 degrees
(deep arches), run beside the other parts."""
from hypothesis import given, settings, strategies as st

from test_invariance import EXAMPLES, OTHERS, SETTINGS, check_invariance


@settings(SETTINGS, max_examples=EXAMPLES // 2)
@given(beta=st.floats(160.0, 230.0, exclude_max=True), **OTHERS)
def test_units_and_mirror_do_not_change_the_answer_deep(beta, t_over_r, n, log_r, log_rho):
    check_invariance(beta, t_over_r, n, log_r, log_rho)
