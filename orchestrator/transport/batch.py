"""Batched transport: many independent realisations carried through one flow record in one model.

An ensemble's realisations (:mod:`orchestrator.studies.ensemble`) share the flume, the column
and the flow, and differ only in their bodies' starts. One MuJoCo model per realisation pays
the engine's per-step Python work (the forcing, the contact bookkeeping, the array copies:
most of a one-body run's cost) once per body. :func:`run_batch` puts the bodies of ``B``
realisations into one model instead and steps them together, so that work is paid once per
step for all of them, and the forcing (:class:`~orchestrator.transport.engine._Forcing`, already
vectorised over bodies) samples the flow at every body's points in one call.

Why the realisations stay independent
-------------------------------------
* **No contact between realisations.** The model has only explicit contact pairs
  (:func:`~orchestrator.transport.mujoco_model.build_model`); each realisation's bodies form one
  ``group`` and body-body pairs are built within a group only, so bodies of different
  realisations pass through each other. A batch of one-body realisations has no body-body pair
  at all; the bodies of a multi-body realisation keep theirs.
* **One constraint island per body.** MuJoCo solves the contacts of bodies that share no
  constraint as separate islands (its default, ``mjDSBL_ISLAND`` off), each to its own
  tolerance, so one body's contacts do not enter another's solve; free bodies without a
  constraint move independently anyway. The warm start, which MuJoCo chooses for the whole
  model at once, is off (:mod:`~orchestrator.transport.mujoco_model`), so each island's solve
  starts from its own state: a batch gives the one-at-a-time first strikes to rounding (1e-13
  relative on the 1-debris record, 32 realisations at B = 32). Rounding itself still differs
  (MuJoCo's and numpy's vector arithmetic over arrays of other lengths), and a rebound
  sequence after a first strike is chaotic enough to magnify it: later strikes can differ.
* **The same step.** The time step is the smallest any contact needs; realisations of one scene
  have the same bodies, so it is the one-at-a-time step.
* **Strikes.** A strike found in one realisation undoes and retakes the step for the whole
  model (:func:`~orchestrator.transport.engine.run_transport`); the other bodies retake the
  same step from the same state, which is deterministic, so their motion is unchanged. The
  retaken steps cost a few per cent at the ensembles' batch sizes (docs/ensembles.md).

The result is split back (:func:`split_batch`): each realisation gets its own
:class:`~orchestrator.transport.engine.TransportResult` with its bodies' own names, its events
numbered from 1 in the order they happened (as a run of that realisation alone numbers them),
and its pulses and strike states under those numbers. ``wall_s`` and ``pulse_wall_s`` are the
batch's divided evenly among its realisations (the stepping is shared and cannot be told apart).
"""

from __future__ import annotations

import dataclasses
from typing import Sequence

import numpy as np
import pandas as pd

from orchestrator.core.errors import InputError
from orchestrator.transport.engine import TransportResult, TransportSettings, run_transport
from orchestrator.transport.flow import FlowField
from orchestrator.scene.schema import DebrisBody
from orchestrator.transport.mujoco_model import FlumeBounds, PlacedColumn, with_start

__all__ = ["batch_bodies", "run_batch", "split_batch"]


def batch_bodies(realisations: Sequence[Sequence[DebrisBody]]) -> tuple[list[DebrisBody], list[int], dict]:
    """The bodies of all ``realisations`` renamed ``r<k>_<name>`` (k the realisation's place in
    the batch), their groups (k), and each new name's (k, original name)."""
    bodies, groups, owner = [], [], {}
    for k, placed in enumerate(realisations):
        names = [b.name for b in placed]
        if len(set(names)) != len(names):
            raise InputError("bodies", f"names must be unique within a realisation, got {names}")
        for b in placed:
            name = f"r{k}_{b.name}"
            bodies.append(with_start(b, name=name))
            groups.append(k)
            owner[name] = (k, b.name)
    if not bodies:
        raise InputError("bodies", "give at least one realisation with a body")
    return bodies, groups, owner


def run_batch(realisations: Sequence[Sequence[DebrisBody]], flume: FlumeBounds, t_end_s: float,
              flow: FlowField | None = None, column: PlacedColumn | None = None,
              settings: TransportSettings | None = None) -> list[TransportResult]:
    """Carry every realisation's bodies through ``flow`` in one model (module notes); one
    :class:`TransportResult` per realisation, in order, as
    :func:`~orchestrator.transport.engine.run_transport` would give it for that realisation alone."""
    bodies, groups, owner = batch_bodies(realisations)
    result = run_transport(bodies, flume, t_end_s, flow=flow, column=column, settings=settings, groups=groups)
    return split_batch(result, len(realisations), owner)


def _realisation_of(names: pd.Series, owner: dict) -> tuple[np.ndarray, pd.Series]:
    pairs = [owner[n] for n in names]
    return np.array([k for k, _ in pairs], dtype=int), pd.Series([b for _, b in pairs], index=names.index, dtype=names.dtype)


def split_batch(result: TransportResult, n: int, owner: dict) -> list[TransportResult]:
    """Split a batch's result into its ``n`` realisations' (module notes); ``owner`` maps each
    batch body name to (realisation, original name)."""
    tracks = result.tracks
    k_track, base = _realisation_of(tracks["body"], owner)
    tracks = tracks.assign(body=base)
    impacts, contacts = result.impacts, result.body_contacts
    k_imp, base = _realisation_of(impacts["body"], owner)
    impacts = impacts.assign(body=base)
    k_con, base = _realisation_of(contacts["body"], owner)
    contacts = contacts.assign(body=base, other=[owner[o][1] for o in contacts["other"]])
    gone = result.departures
    k_gone, base = _realisation_of(gone["body"], owner)
    gone = gone.assign(body=base)
    # every event is in one of the two tables: its realisation, then its number there
    realisation_of_event = dict(zip(impacts["event"].astype(int), k_imp)) | dict(zip(contacts["event"].astype(int),
                                                                                     k_con))
    local: dict[int, int] = {}
    counts = [0] * n
    for number in sorted(realisation_of_event):
        k = realisation_of_event[number]
        counts[k] += 1
        local[number] = counts[k]
    impacts = impacts.assign(event=[local[int(e)] for e in impacts["event"]])
    contacts = contacts.assign(event=[local[int(e)] for e in contacts["event"]])
    out = []
    for k in range(n):
        mine = {number for number, r in realisation_of_event.items() if r == k}
        out.append(dataclasses.replace(
            result,
            tracks=tracks[k_track == k].reset_index(drop=True),
            impacts=impacts[k_imp == k].reset_index(drop=True),
            body_contacts=contacts[k_con == k].reset_index(drop=True),
            wall_s=result.wall_s / n, pulse_wall_s=result.pulse_wall_s / n,
            pulses={local[e]: p for e, p in result.pulses.items() if e in mine},
            strike_states={local[e]: s for e, s in result.strike_states.items() if e in mine},
            departures=gone[k_gone == k].reset_index(drop=True)))
    return out
