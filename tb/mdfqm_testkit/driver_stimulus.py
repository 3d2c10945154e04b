"""Stimulus of the gate driver (tb/test_driver.py, and the mutation campaign's driver block):
core-like update strobes with every runtime setting moving, and the scenarios of the driver's
rules (fault chatter, faults in dead times, enable and dead time changed inside updates, short
pulses, the fault reaction), with the expected outputs from
:class:`mdfqm_model.driver.GateDriverModel` and the gate-safety check of every trace."""

from mdfqm_model.driver import DRIVER_INPUTS, DRIVER_OUTPUTS, GateDriverModel, check_gate_safety

#: what the fault-reaction scenario must reach (the ASC ones only with the ASC built in):
#: each source's first rise with each reaction; an ASC entered while a leg had its ASC switch
#: on, the other switch on, the other switch inside its minimum pulse, both off inside a dead
#: time; an ASC ended by ALL_OFF, by the clears, by a later source with all off, by a reset; a
#: later source's ASC and a new reaction input ignored while one is in force; code 3 all off
REACTION_BINS = {
    *(("first", source, code) for source in ("fault", "watchdog", "both") for code in (0, 1, 2)),
    *(("entry", state) for state in ("asc_on", "other_on", "other_in_min_pulse", "dead_time")),
    "all_off_ends_asc", "clear_ends_asc", "second_source_ends_asc", "reset_ends_asc",
    "second_asc_ignored", "new_input_ignored", "code_3_all_off"}
#: without the ASC built in: every source's rise, and an ASC code given that acts as all off
REACTION_BINS_ALL_OFF = {("first", "fault", 0), ("first", "watchdog", 0), "asc_code_all_off"}

INPUTS = DRIVER_INPUTS


#: clocks of the long scenario after its rounds: the legs disabled past the counters'
#: saturation (plus this), then enabled (this long)
LONG_TAIL = (64, 200)


def long_round(k: int) -> int:
    """Clocks of round ``k`` of the ``long_times`` scenario: a minimum pulse and a dead time
    of ``2**k`` to ``2**(k + 1) - 1`` clocks each, and room to turn on after them."""
    return (4 << k) + 64


def long_times_cycles(time_width: int) -> int:
    """Clocks of the ``long_times`` scenario: one round per bit of the counters (the minimum
    pulse and the dead time in that bit's octave), then the legs disabled for longer than the
    counters' saturation (``2**time_width`` clocks) and enabled."""
    return (sum(long_round(k) for k in range(time_width)) + (1 << time_width) + sum(LONG_TAIL))


def long_times_schedule(rng, p) -> dict:
    """The settings of the ``long_times`` scenario by the clock they take effect: (DEAD,
    MIN_PULSE, enable, lowered), ``lowered`` True in a round whose DEAD the scenario lowers
    once a leg waits it out (:func:`waits_on_remembered`). Rounds of rising octaves (a dead
    time in force is never shortened, so the longest come last), then the largest dead time
    (``2**time_width - 1``: it elapses only once the count has saturated) with the legs
    disabled past the counters' saturation, then enabled: every commanded switch on at once."""
    width, top = p["time_width"], (1 << p["time_width"]) - 1
    schedule, at = {}, 0
    for k in range(width):
        octave = (1 << k, min(top, (2 << k) - 1))
        schedule[at] = (rng.randint(*octave), rng.randint(*octave), 1, True)
        at += long_round(k)
    schedule[at] = (top, 0, 0, False)
    schedule[at + (top + 1) + LONG_TAIL[0]] = (top, 0, 1, False)
    return schedule


def waits_on_remembered(leg, dead: int) -> bool:
    """The leg is off, inside a dead time that began under ``dead`` (its last on cycle's):
    lowering DEAD now leaves it waiting for the remembered one (the rule "a dead time already
    running is never shortened")."""
    return (not (leg.up or leg.lo) and leg.dt_run == leg.dead_clamped(dead)
            and leg.cnt + 1 < leg.dt_run)


def remembered_dead_times(legs, dead: int) -> list:
    """Per leg, the octave of the remembered dead time (``dt_run``) that decides a turn-on in
    this clock, or None: the leg is off, its ``dt_run`` is above the clamped ``dead`` it acts
    on, and its count reaches ``dt_run`` now."""
    return [leg.dt_run.bit_length() - 1
            if (not (leg.up or leg.lo) and leg.dt_run > leg.dead_clamped(dead)
                and leg.cnt + 1 == leg.dt_run) else None
            for leg in legs]


class Stimulus:
    """A core-like source of update strobes plus the runtime settings of one scenario."""

    def __init__(self, rng, p):
        self.rng, self.p = rng, p
        self.n, self.top = p["phases"], (1 << p["time_width"]) - 1
        self.period, self.phase, self.h = 10, 0, 0
        self.enable, self.dead, self.min_pulse = 1, p["dead_min"], 0

    def dead_choice(self):
        # the largest value only with narrow counters: a dead time in force is never shortened
        # (not even by a reset), so 65535 would silence the legs of the following tests
        big = self.top if self.top < 100 else 200
        return self.rng.choice([0, 1, 2, self.p["dead_min"], 3, 5, 9, min(17, self.top), big])

    def update_strobe(self):
        """An update every ``period`` clocks; h changes a few legs at a time."""
        rng = self.rng
        self.phase += 1
        if self.phase < self.period:
            return 0
        self.phase = 0
        flips = rng.choice([0, 1, 1, 2, self.n])
        for _ in range(flips):
            self.h ^= 1 << rng.randrange(self.n)
        return 1


class DriverRun:
    """The driver's scenarios as one simulation runs them, one after the other: the model is
    carried from one scenario to the next, because the leg's ``dt_run`` and the fault
    synchroniser are not reset (by design), so the design enters each scenario with the state
    the previous one left. A failing scenario can therefore make later ones of the same run fail
    too; the first failure is the real one. ``p``: the driver's parameters (phases, dead_min,
    time_width, upper_active_low, lower_active_low, asc)."""

    def __init__(self, p):
        self.p = p
        self.model = GateDriverModel(p["phases"], p["dead_min"], p["time_width"],
                                     p["upper_active_low"], p["lower_active_low"], p["asc"])
        #: the inputs of the last clock driven: held through the reset clocks that follow
        self.last = {name: 0 for name in INPUTS}

    def reset_clocks(self, count=2):
        """The reset clocks that start a scenario (``harness.start``: ``rst`` high, the other
        inputs as the previous scenario left them): a list of (inputs, model outputs)."""
        steps = []
        for _ in range(count):
            inputs = {**self.last, "rst": 1}
            steps.append((inputs, self.model.step(**inputs)))
        return steps

    def generate(self, rng, scenario, cycles, hit=None):
        """One scenario after its reset clocks: (inputs, expected outputs, turn-ons), with
        the fault-reaction bins reached added to ``hit`` (a set) if given."""
        self.reset_clocks()
        stim, expected, turn_ons = _generate(self.model, rng, scenario, self.p, cycles, hit)
        self.last = {name: stim[name][-1] for name in INPUTS}
        return stim, expected, turn_ons


def reaction_bins(model, inputs, before, hit):
    """Add to ``hit`` the fault-reaction bins (:data:`REACTION_BINS`) of one clock:
    ``before`` is the model's state before the clock's step (:func:`reaction_state`)."""
    r_prev, f_prev, w_prev, fault_active, legs = before
    r = model.reaction
    stop, fa = inputs["stop"], fault_active
    rise_f, rise_w = fa and not f_prev, stop and not w_prev
    code_f, code_w = inputs["reaction_fault"], inputs["reaction_watchdog"]
    if inputs["rst"]:
        if r_prev:
            hit.add("reset_ends_asc")
        return
    if (rise_f or rise_w) and not (f_prev or w_prev) and not inputs["all_off"]:
        source = "both" if rise_f and rise_w else "fault" if rise_f else "watchdog"
        hit.add(("first", source, r))
        code = code_f if rise_f else code_w
        if code == 3 and r == 0:
            hit.add("code_3_all_off")
        if code in (1, 2) and not model.asc:
            hit.add("asc_code_all_off")
    if r and not r_prev:
        for up, lo, on_for, min_pulse, dt_req in legs:
            asc_on = lo if r == 1 else up
            other_on = up if r == 1 else lo
            if asc_on:
                hit.add(("entry", "asc_on"))
            elif other_on:
                hit.add(("entry", "other_in_min_pulse" if on_for < min_pulse else "other_on"))
            elif on_for < dt_req:
                hit.add(("entry", "dead_time"))
    if r_prev and not r:
        if inputs["all_off"]:
            hit.add("all_off_ends_asc")
        elif not (fa or stop):
            hit.add("clear_ends_asc")
        elif (rise_f and code_f in (0, 3)) or (rise_w and code_w in (0, 3)):
            hit.add("second_source_ends_asc")
    if r_prev and r == r_prev:
        if (rise_f and code_f in (1, 2) and code_f != r) or \
                (rise_w and code_w in (1, 2) and code_w != r):
            hit.add("second_asc_ignored")
        elif (code_f in (1, 2) and code_f != r) or (code_w in (1, 2) and code_w != r):
            hit.add("new_input_ignored")


def reaction_state(model, inputs):
    """The model's state that :func:`reaction_bins` compares (before a step): the reaction in
    force, the sources of the clock before, this clock's fault, and per leg (up, lo, clocks in
    the present state + 1, the minimum pulse and dead time in force)."""
    legs = [(leg.up, leg.lo, leg.cnt + 1, model.min_pulse_seen,
             max(leg.dt_run, leg.dead_clamped(model.dead_seen))) for leg in model.legs]
    return (model.reaction, model.fault_prev, model.stop_prev,
            int(bool(model.fault_input or model.fault)), legs)


class ReactionEpisodes:
    """The fault-reaction scenario: every 160 clocks an episode, a fault, a watchdog stop or
    both (in one clock or one after the other) with random reactions (codes 0-3; the first
    fifteen episodes walk every source and reaction, code 3, a reset in an ASC and a second
    source after the first), at a random clock of short updates (so that legs are on, inside
    their minimum pulse or inside a dead time), maybe a new reaction input, ALL_OFF or a
    reset during it, then the clears."""

    LENGTH = 160

    def __init__(self, rng, s):
        self.rng, self.s = rng, s
        self.plan = {}
        # first every source with every reaction once, two with a reset in an ASC; then random
        self.schedule = [(kind, (code, code or 1) if kind == "both" else (code, code), False)
                         for kind in ("fault", "watchdog", "both") for code in (0, 1, 2)]
        self.schedule += [("fault", (1, 0), True), ("watchdog", (0, 2), True),
                          ("fault_then_watchdog", (1, 2), False),
                          ("watchdog_then_fault", (1, 2), False),
                          ("fault_then_watchdog", (2, 0), False), ("fault", (3, 0), False)]
        rng.shuffle(self.schedule)

    def new_plan(self):
        rng, s = self.rng, self.s
        s.period = rng.choice([3, 5, 7, 11, 16])
        s.dead = rng.choice([self.s.p["dead_min"], 3, 5, 8])
        s.min_pulse = rng.choice([0, 0, 4, 9])
        start = rng.randrange(10, 40)
        kind = rng.choice(["fault", "watchdog", "both", "fault_then_watchdog",
                           "watchdog_then_fault"])
        codes = (rng.choice([0, 1, 1, 2, 2, 3]), rng.choice([0, 1, 1, 2, 2, 3]))
        reset = rng.random() < 0.08
        all_off, new_codes = rng.random() < 0.4, rng.random() < 0.3
        if self.schedule:
            kind, codes, reset = self.schedule.pop()
            all_off = new_codes = False
        second = start + rng.randrange(5, 30)
        self.plan = {
            "fault": (start - 2 if kind in ("fault", "both", "fault_then_watchdog")
                      else second - 2 if kind == "watchdog_then_fault" else None),
            "watchdog": (start if kind in ("watchdog", "both", "watchdog_then_fault")
                         else second if kind == "fault_then_watchdog" else None),
            "codes": codes,
            "new_codes": new_codes and (rng.randrange(4), rng.randrange(4)),
            "new_at": start + rng.randrange(3, 40),
            "all_off": start + rng.randrange(3, 80) if all_off else None,
            "reset": start + rng.randrange(8, 50) if reset else None,
            "release": start + rng.randrange(60, 100),
        }

    def inputs(self, cycle):
        """(fault_in, clear, stop, rst, all_off, (reaction_fault, reaction_watchdog))."""
        k = cycle % self.LENGTH
        if k == 0:
            self.new_plan()
        plan = self.plan
        codes = plan["codes"]
        if plan["new_codes"] and k >= plan["new_at"]:
            codes = plan["new_codes"]
        fault_in = int(plan["fault"] is not None and plan["fault"] <= k < plan["release"])
        stop = int(plan["watchdog"] is not None and plan["watchdog"] <= k < plan["release"] + 3)
        clear = int(k in (plan["release"] + 3, plan["release"] + 10))
        return (fault_in, clear, stop, int(k == plan["reset"]), int(k == plan["all_off"]),
                codes)


def _generate(model, rng, scenario, p, cycles, hit):
    n, dead_min = p["phases"], p["dead_min"]
    dt_run0 = [leg.dt_run for leg in model.legs]
    s = Stimulus(rng, p)
    episodes = ReactionEpisodes(rng, s)
    codes = (0, 0)
    stim = {name: [] for name in INPUTS}
    expected = {name: [] for name in DRIVER_OUTPUTS}
    up, lo, in_force = [], [], []
    chatter = stopped = 0
    to_lower = False
    for cycle in range(cycles):
        rst = fault_in = clear = all_off = 0
        if scenario == "random":
            if rng.random() < 0.002:
                s.period = rng.choice([1, 2, 3, 8, 13, 30, 60])
            if rng.random() < 0.004:
                s.enable ^= 1
            if rng.random() < 0.01:
                s.dead = s.dead_choice()
            if rng.random() < 0.005:
                s.min_pulse = rng.choice([0, 1, 3, 10, 30, min(s.top, 200)])
            if rng.random() < 0.002:
                chatter = rng.randint(1, 12)
            if rng.random() < 0.002:        # a watchdog trip: stop held a while, then cleared
                stopped = rng.choice([1, 2, 7, 40])
            clear = int(rng.random() < 0.03)
            rst = int(rng.random() < 0.0007)
            if rng.random() < 0.003:
                codes = (rng.randrange(4), rng.randrange(4))
            all_off = int(rng.random() < 0.003)
        elif scenario == "fault_chatter":
            # chattering input: glitches of one clock, bursts, a long assertion; clears
            # attempted while active and while inactive
            if cycle % 300 == 0:
                s.period = rng.choice([5, 9, 20])
            if rng.random() < 0.01:
                chatter = rng.choice([1, 2, 5, 40])
            clear = int(rng.random() < 0.05)
        elif scenario == "fault_in_dead_time":
            s.period = 25
            s.dead = 9 if cycle < cycles // 2 else dead_min
            if s.phase in (rng.randint(0, 12), 1) and rng.random() < 0.3:
                fault_in = 1
            clear = int(s.phase == 20)
        elif scenario == "enable_mid_update":
            if cycle % 400 == 0:
                s.period = rng.choice([6, 11, 23])
            if rng.random() < 0.05:
                s.enable ^= 1
        elif scenario == "dead_change":
            s.period = rng.choice([s.period, s.period, 19, 31]) if s.phase == 0 else s.period
            # change the dead time a few clocks after an update: inside running dead times
            if s.phase in (1, 2, 3, 5, 8) and rng.random() < 0.3:
                s.dead = s.dead_choice()
        elif scenario == "long_times":
            # the widest settings, DEAD and MIN_PULSE in every octave up to 2**time_width - 1,
            # and a state held past the counters' saturation (long_times_schedule); in each
            # round, DEAD lowered to 0 once a leg waits out the round's dead time: its turn-on
            # then waits for the dead time remembered from its last on cycle
            if cycle == 0:
                s.period, schedule = 10, long_times_schedule(rng, p)
            if cycle in schedule:
                s.dead, s.min_pulse, s.enable, to_lower = schedule[cycle]
            elif to_lower and any(waits_on_remembered(leg, model.dead_seen)
                                  for leg in model.legs):
                s.dead, to_lower = 0, False
        elif scenario == "min_pulse" and cycle % 200 == 0:
            s.period = rng.choice([1, 2, 3, 4, 6, 9])
            s.dead = rng.choice([dead_min, 2, 3, 5])
            s.min_pulse = rng.choice([0, 1, 2, 4, 7, 12])
        if chatter:
            chatter -= 1
            fault_in = rng.randint(0, 1) if chatter > 1 else 1
        stop = int(stopped > 0)
        stopped = max(stopped - 1, 0)
        if scenario == "fault_reaction":
            fault_in, clear, stop, rst, all_off, codes = episodes.inputs(cycle)
        update = s.update_strobe()
        h = s.h if update or rng.random() < 0.5 else rng.randrange(1 << n)  # noise between
        inputs = {"rst": rst, "h": h, "update": update, "enable": s.enable, "dead": s.dead,
                  "min_pulse": s.min_pulse, "fault_in": fault_in, "fault_clear": clear,
                  "stop": stop, "reaction_fault": codes[0], "reaction_watchdog": codes[1],
                  "all_off": all_off}
        in_force.append(model.dead_in_force)     # the legs act on last clock's dead
        before = reaction_state(model, inputs) if hit is not None else None
        # the legs act on the dead time of the clock before (dead_seen)
        remembered = remembered_dead_times(model.legs, model.dead_seen)
        out = model.step(**inputs)
        if hit is not None:
            reaction_bins(model, inputs, before, hit)
            hit.update(("remembered_dead_time", octave)
                       for octave, leg in zip(remembered, model.legs, strict=True)
                       if octave is not None and (leg.up or leg.lo))
        for name in INPUTS:
            stim[name].append(inputs[name])
        for name in DRIVER_OUTPUTS:
            expected[name].append(out[name])
        mask = (1 << n) - 1
        up.append(out["upper"] ^ (mask if p["upper_active_low"] else 0))
        lo.append(out["lower"] ^ (mask if p["lower_active_low"] else 0))
    kill = [f | k for f, k in zip(expected["fault_input"], stim["stop"], strict=True)]
    turn_ons = check_gate_safety(up, lo, n, dead=in_force, kill=kill,
                                 rst=stim["rst"], dt_run0=dt_run0, reaction=expected["reaction"])
    return stim, expected, turn_ons


