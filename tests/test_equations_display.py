"""Readable equations: the shared-subexpression form is the same system."""

import numpy as np
import sympy as sp

from mechcont.models import load_model


def test_shared_form_evaluates_to_the_same_residuals():
    s = load_model("overcentre.toml", LU=0.7)
    text = s.pretty(shared=True)
    env = {n: sp.Symbol(n, real=True) for n in s.names}
    reps, rows = {}, []
    for line in text.splitlines():
        if line.startswith("w") and " = " in line and ":" not in line.split(" = ")[0]:
            name, expr = line.split(" = ", 1)
            reps[name] = sp.sympify(expr, locals={**env, **reps})
        else:
            rows.append(sp.sympify(line.split(": ", 1)[1].rsplit(" = 0", 1)[0], locals={**env, **reps}))
    assert len(rows) == len(s.equations) and reps  # something was shared
    rng = np.random.default_rng(1)
    x = s.defaults() + rng.normal(0, 0.05, len(s.names))
    subs = dict(zip(env.values(), x))
    got = np.array([float(r.xreplace(subs)) for r in rows])
    assert np.allclose(got, s.residual(x), rtol=1e-12, atol=1e-12)
