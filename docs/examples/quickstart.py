"""A tour of magrod's public API, as a researcher would run it in a notebook.

Run from anywhere, the repository root included:  python docs/examples/quickstart.py
(tests/test_quickstart.py runs it and checks what it prints).  About 20-30 s on a warm heyoka JIT cache.
"""
import matplotlib

matplotlib.use("Agg")  # a script: no screen (a notebook keeps its inline backend; magrod never switches it)

import magrod as mr  # noqa: E402

# the rod and a paper panel (fig:poincare1a): parameters and the start on the energy level h = 0.9
p = mr.RodParams(m=1.7, mu=0.4, gamma=3, delta=3, lam=0.135)
start = mr.panel("4a")
assert start.params == p

# a Poincare section, verified inside (max |Hbar - h| and Casimir drift against the library's tolerances)
sec = mr.poincare_section(p, h=0.9, theta0=0.1, ptheta0=0.5, iterates=2000)
print("section:", sec.success, sec.points.shape, f"max|dH| = {sec.max_abs_dH:.1e}")
sec = mr.poincare_section(start, iterates=2000)  # the same from the panel
ax = sec.plot()

# the chaos indicators of that orbit, with the history lambda(t)
ly = mr.lyapunov(start, t_max=3000)
print("lyapunov:", f"lyap = {ly.lyap:.4f}, growth exponent = {ly.growth_exponent:.2f}, chaotic = {ly.chaotic}",
      f"history {ly.times.shape}")

# a small chaos map around the panel (in this process; pass client=dask.distributed.Client(...) for a cluster)
cm = mr.chaos_map(x=("lam", 0.12, 0.2, 4), y=("gamma", 2.0, 3.5, 3), panel="4a", t_max=1000)
ds = cm.to_xarray()
print("chaos map:", cm.success, dict(ds.sizes), f"fraction chaotic = {cm.fraction_chaotic:.2f}")

# the closed-form lambdabar = 0 homoclinic orbit of the extensible rod (paper sec. 6)
orb = mr.homoclinic_orbit(mr.System(m=1.7, gamma=1.0, mu=0, lam=0))
print("homoclinic:", orb.success, f"theta_max = {orb.theta_max:.4f}")

# the saddle at the panel's parameters: mu > 2 lambdabar, so the helical periodic saddle (mu = 2 lambdabar: the
# straight rod)
sad = mr.saddle(p)
print("saddle:", sad.kind, f"period {sad.T:.4f}")

# symmetric multipulse homoclinic orbits near fig:multimodal1 (mu > 2 lambdabar: to the periodic saddle), a branch
# of the first one in mu, and its rod in space
q = mr.RodParams(m=1.7, mu=0.0025, gamma=1, delta=1, lam=0.001)
orbits = mr.multipulse_orbits(q, max_pulses=2)
print("multipulse:", orbits.success, "pulses", orbits.pulses)
branch = mr.continue_branch(q, orbits[0], parameter="mu", steps=10)
print("branch:", branch.success, f"{branch.u.shape[0]} points, max residual {branch.residuals.max():.1e}")
rod = mr.rod_shape(q, orbits[0])
print("rod:", rod.success, f"length {rod.length:.3f}")

# the splitting of the separatrix at a = 2b, in two precisions, against the derived leading term
spl = mr.splitting(mr.System(m=1.7, gamma=1, delta=1), a=2, b=1, eps=[0.02, 0.014, 0.01, 0.007, 0.005])
print("splitting:", spl.kind, f"psi_u ~ eps^{spl.fit_exponent:.3f}, derived leading term to "
      f"{spl.leading_digits:.1f} digits")

# the symbolic integrability checks (from the checked-in derivation; subs= recomputes live with SymPy)
rep = mr.integrability_report()
print("integrability:", rep.statuses["casimirs"], "| disagreements with the paper:",
      ", ".join(rep.disagreements_with_paper))
