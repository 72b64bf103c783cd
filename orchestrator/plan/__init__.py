"""Stage 2, the plan: every modelling decision for a scene (domain, mesh, bodies, coupling, time step,
decomposition), with its reason, as a ModelPlan written to plan.json."""
