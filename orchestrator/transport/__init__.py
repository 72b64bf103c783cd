"""One-way coupled debris transport: bodies carried through a recorded flow on MuJoCo.

:mod:`~orchestrator.transport.flow` holds the recorded flow (:class:`FlowField`);
:mod:`~orchestrator.transport.engine` builds the MuJoCo model of the flume, the column and
the bodies and runs them through the flow (:func:`run_transport`), the hydrodynamic forcing
coming from :mod:`analytical.hydrodynamics`.
"""
