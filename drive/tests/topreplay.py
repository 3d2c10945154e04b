"""The drop-in top's clock-level golden model programmed through its Wishbone registers as a
firmware would: the reference the drive tests compare their fast paths with."""

from mdfqm_model.top import TopModel
from mdfqm_spec.contract import FEWEST_TRANSITIONS, MODES
from mdfqm_spec.regmap import (
    ADC_OFFSET,
    CMD,
    CMD_REF_COMMIT,
    CTRL,
    CTRL_ENABLE,
    CTRL_ZERO_POLICY,
    DEAD,
    MIN_PULSE,
    MODULATION,
    MODULATION_BITS_SHIFT,
    MODULATION_MODE_SHIFT,
    OSR,
    PERIOD,
    REF_BASE,
)


class WishboneFirmware:
    """Single Wishbone-classic writes to a :class:`TopModel`, one clock each plus the ack's."""

    def __init__(self, top: TopModel):
        self.top = top
        self.cycle = 0
        self.pins = []  # (upper, lower, adc_trigger, sync_out) of every clock

    def clock(self, **inputs):
        out = self.top.step(**inputs)
        self.pins.append((out["upper"], out["lower"], out["adc_trigger"], out["sync_out"]))
        self.cycle += 1
        return out

    def write(self, address, value):
        self.clock(wb_cyc=1, wb_stb=1, wb_we=1, wb_adr=address, wb_dat_w=value & 0xFFFFFFFF,
                   wb_sel=0xF)
        self.clock()

    def until_start(self):
        while not self.clock()["sync_out"]:
            pass
        return self.cycle - 1


def run_top(settings, refs, updates):
    """Program the top, start it at a sampling tick that takes ``refs[0]``, then write
    ``refs[m]`` in the middle of control period ``m - 1``. Returns the pins from that tick on."""
    top = TopModel()
    fw = WishboneFirmware(top)
    fw.clock(rst=1)
    modulation = (MODES.index(settings.mode) << MODULATION_MODE_SHIFT
                  | settings.bits << MODULATION_BITS_SHIFT)
    for address, value in ((PERIOD, settings.period), (OSR, 1), (DEAD, settings.dead),
                           (MIN_PULSE, settings.min_pulse), (ADC_OFFSET, settings.adc_offset),
                           (MODULATION, modulation)):
        fw.write(address, value)
    for _ in range(3):  # the period, the mode and OSR 1 in force
        fw.until_start()
    # in the update before the first tick: after its boundary (so that the enable is first
    # taken at the tick update's boundary), the tick's reference, OSR and the enable
    s = fw.until_start()
    while fw.cycle <= s + top.core.long_latency:
        fw.clock()
    for i, code in enumerate(refs[0]):
        fw.write(REF_BASE + i, int(code))
    fw.write(CMD, CMD_REF_COMMIT)
    fw.write(OSR, settings.osr)
    ctrl = CTRL_ENABLE | (CTRL_ZERO_POLICY if settings.zero_policy == FEWEST_TRANSITIONS else 0)
    fw.write(CTRL, ctrl)
    first = fw.until_start()
    period = max(settings.period, 1)
    ref_index = 1
    while fw.cycle < first + updates * period:
        k, phase = divmod(fw.cycle - first, period)
        if (ref_index < len(refs) and k % settings.osr == settings.osr - 1
                and phase == period // 2):
            for i, code in enumerate(refs[ref_index]):
                fw.write(REF_BASE + i, int(code))
            fw.write(CMD, CMD_REF_COMMIT)
            ref_index += 1
        else:
            fw.clock()
    return fw.pins[first:first + updates * period], top
