"""Plants wrong on purpose: every plant check must fail on them."""

from mdfqm_drive.plant import Plant


def _swap_bc(mask):
    return (mask & 1) | ((mask >> 1) & 1) << 2 | ((mask >> 2) & 1) << 1


class SwappedPhases(Plant):
    """Wrong on purpose: legs b and c wired to the motor's phases c and b."""

    def phase_currents(self):
        a, b, c = super().phase_currents()
        return a, c, b

    def pole_voltages(self, upper, lower):
        return super().pole_voltages(_swap_bc(upper), _swap_bc(lower))


class FlippedEmf(Plant):
    """Wrong on purpose: the magnets' flux with the opposite sign in the voltage equations."""

    def __init__(self, motor, *args, **kwargs):
        super().__init__(motor, *args, **kwargs)
        self.motor = _NegativeFlux(motor)


class _NegativeFlux:
    def __init__(self, motor):
        self._m = motor

    def __getattr__(self, name):
        value = getattr(self._m, name)
        return -value if name == "psi_f" else value


class SignRule(Plant):
    """Wrong on purpose: a blanked leg stays on the diode of its current's sign at the start of
    the interval, even after that current has reached zero (motulator's rule, and this plant's
    before its diodes could block)."""

    def advance(self, dt, upper, lower):
        if dt <= 0 or (not (upper | lower) & 7 and self.i_d == self.i_q == 0.0):
            super().advance(dt, upper, lower)
            return
        self._advance_poles(dt, self.pole_voltages(upper, lower), self.phase_currents())
