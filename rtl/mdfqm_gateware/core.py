"""The MDFQM core: reference stage, integrators, sort1, candidates, sort2, decoder, sequencer."""

from types import SimpleNamespace

from amaranth import Module, signed
from amaranth.lib import data, stream, wiring
from amaranth.lib.wiring import In, Out, connect

from mdfqm_spec.contract import Contract, loop_latency, validate_rule
from mdfqm_spec.validate import validate_bool, validate_positive

from .integrator import Integrator
from .reference import ReferenceStage
from .selector import ArgMax, Candidates, StateDecoder, candidate_width
from .sequencer import UpdateSequencer
from .sort import SortNetwork

__all__ = ["MdfqmCore", "build_loop", "loop_ports"]


class MdfqmCore(wiring.Component):
    """Multi-dimensional feedback quantisation (the paper's Case II, 0-bit pulse-width resolution).

    One update every ``period`` clocks: ``T = X + R``; sort1; duties (or exact scores) of the
    staircase states; sort2 picks the winner; it is un-permuted to the gate state ``h``; its
    phase voltage is fed back into the integrators. Every bit and every clock follows
    :mod:`mdfqm_spec.contract` and is predicted by :class:`mdfqm_model.clock.CoreModel`.

    Ports
    -----
    ref : In(stream.Signature(ArrayLayout(signed(width), phases)))
        Phase references (``2**(width-2)`` codes per Vdc, any common mode). One beat is taken at
        a time and used from the next sampling tick on (zero-order hold between ticks).
    period : In(16)
        Clocks per update, sampled at each update start; values below ``latency`` are used as
        ``latency`` and flagged by ``period_clamped``.
    osr : In(8)
        Updates per reference sample, sampled at each update start; 0 acts as 1.
    zero_policy : In(1)
        0: the zero state is all-off (the paper). 1: all-off or all-on, whichever needs fewer
        transitions from the previous state. Sampled at each update start.
    sync_in : In(1)
        Share update boundaries between instances: high in a cycle in which the update in
        flight has committed by the next cycle (``phase + 1 >= latency``) makes the next cycle
        an update start; ignored earlier. Wire another instance's ``start`` here.
    h : Out(phases)
        Gate state, bit i = upper switch of leg i on. Changes only with ``update``.
    update : Out(1)
        One-clock strobe: ``h`` (and ``saturated``) took this update's value this cycle.
    start : Out(1)
        High in the first clock of each update (use as sync out).
    sample : Out(1)
        High at an update start that samples the reference.
    saturated : Out(1)
        The last update hit the integrator bound and held the integrators (overmodulation).
    period_clamped : Out(1)
        The requested period was below ``latency`` at the last update start.
    elapsed : Out(16)
        Clocks since the last update start: 0 in a start cycle (``start`` high), then 1, 2, ...
        up to the period minus one (combinational from registers): an ADC trigger or any
        event at a fixed offset into the update compares with it.

    Parameters
    ----------
    phases : int >= 3
    width : int in [min_width(phases), 32]
        Reference width; ``FULL = 2**(width-2) >= 16 * phases``.
    rule : "largest_duty" | "exact_nearest"
        Selection rule (identical results for three phases).
    formal : bool
        Emit the blocks' properties for the formal tests, none of them an assumption: the
        integrators never wrap (property 5), sort1 is a stable descending sort, sort2 picks the
        first maximum, the state is a candidate and the feedback its phase voltage (property 6).
        The drop-in Verilog (``False``) has none.

    Attributes
    ----------
    latency : int
        Loop latency in clocks = the smallest update period (8 for three phases).
    """

    def __init__(self, phases: int = 3, width: int = 16, rule: str = "largest_duty",
                 formal: bool = False):
        self.contract = Contract(phases, width)
        self.rule = validate_rule(rule, phases)
        self.formal = validate_bool(formal, "formal")
        self.phases, self.width = phases, width
        self.latency = loop_latency(phases, rule)
        super().__init__(loop_ports(phases, width))

    def elaborate(self, platform):
        m = Module()
        m.submodules.sequencer = sequencer = UpdateSequencer(self.latency)
        loop = build_loop(m, self, sequencer, self.width - 2, h_prev=self.h)
        validate_positive(self.latency, "latency", minimum=1 + loop.sort1.latency + 3)
        m.d.comb += [
            loop.integrator.i_commit.eq(loop.decoder.o_valid),
            loop.integrator.i_units_n.eq(loop.decoder.o_units_n),
        ]
        m.d.sync += self.update.eq(loop.decoder.o_valid)
        with m.If(loop.decoder.o_valid):
            m.d.sync += self.h.eq(loop.decoder.o_h)
        return m


def loop_ports(phases: int, width: int, extra_inputs=None, extra_outputs=None) -> dict:
    """The ports of :class:`MdfqmCore` (documented there), with a wider component's own inputs
    and outputs placed after the core's."""
    return {
        "ref": In(stream.Signature(data.ArrayLayout(signed(width), phases))),
        "period": In(16),
        "osr": In(8),
        "zero_policy": In(1),
        "sync_in": In(1),
        **(extra_inputs or {}),
        "h": Out(phases),
        "update": Out(1),
        "start": Out(1),
        "sample": Out(1),
        "saturated": Out(1),
        "period_clamped": Out(1),
        "elapsed": Out(16),
        **(extra_outputs or {}),
    }


def build_loop(m, component, sequencer, unit_shift: int, h_prev) -> SimpleNamespace:
    """The blocks of the MDFQM loop and their wiring, shared by :class:`MdfqmCore` and the
    gating-signal generator: reference stage, integrators (feedback in units of
    ``2**unit_shift``), sort1, candidates, sort2, decoder (zero policy against ``h_prev``), fed
    by ``sequencer`` and ``component``'s ``ref``, ``period``, ``osr``, ``zero_policy``,
    ``sync_in``; drives its ``start``, ``sample``, ``saturated``, ``period_clamped``. The
    caller wires the commit (``integrator.i_commit``, ``i_units_n``) and the outputs ``h`` and
    ``update``."""
    n, width, formal = component.phases, component.width, component.formal
    c = component.contract
    m.submodules.reference = reference = ReferenceStage(n, width)
    # the generator's feedback (finer than FULL) comes wide and through its mode select: its
    # integrators keep a copy, so that their bound check ends at one flop (Integrator)
    m.submodules.integrator = integrator = Integrator(n, width, unit_shift=unit_shift,
                                                      formal=formal, formal_sums=False,
                                                      kept_copy=unit_shift != width - 2)
    # sort1 gives the candidates the values they subtract inverted (rho_held_inverted)
    candidates = Candidates(n, width, component.rule)
    m.submodules.sort1 = sort1 = SortNetwork(n, c.t_width, formal=formal,
                                             inverted_outputs=candidates.rho_inverted)
    m.submodules.candidates = candidates
    m.submodules.sort2 = sort2 = ArgMax(n, candidate_width(n, width), formal=formal)
    m.submodules.decoder = decoder = StateDecoder(n, formal=formal, assume_inputs=False)

    connect(m, wiring.flipped(component.ref), reference.ref)
    m.d.comb += [
        sequencer.period.eq(component.period),
        sequencer.osr.eq(component.osr),
        sequencer.zero_policy.eq(component.zero_policy),
        sequencer.sync_in.eq(component.sync_in),
        reference.tick_next.eq(sequencer.tick_next),
        integrator.i_start.eq(sequencer.start),
        integrator.i_r.eq(reference.r),
        sort1.i_values.eq(integrator.o_t),
        candidates.i_rho.eq(sort1.o_values),
        candidates.i_valid.eq(sort1.o_valid),
        sort2.i_values.eq(candidates.o_values),
        sort2.i_valid.eq(candidates.o_valid),
        # T, and so sort1's outputs, hold still until the next start (period >= latency).
        decoder.i_perm.eq(sort1.o_index),
        decoder.i_j.eq(sort2.o_index),
        decoder.i_policy.eq(sequencer.policy),
        decoder.i_h_prev.eq(h_prev),
        decoder.i_valid.eq(sort2.o_valid),
        component.start.eq(sequencer.start),
        component.sample.eq(sequencer.tick),
        component.saturated.eq(integrator.o_saturated),
        component.period_clamped.eq(sequencer.period_clamped),
        component.elapsed.eq(sequencer.elapsed),
    ]
    m.d.sync += sort1.i_valid.eq(sequencer.start)
    return SimpleNamespace(reference=reference, integrator=integrator, sort1=sort1,
                           candidates=candidates, sort2=sort2, decoder=decoder)
