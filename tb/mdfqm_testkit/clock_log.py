"""The clock logs of the Verilator harnesses that run the C firmware against the drop-in top
(sw/sim/harness.cpp, sw/sim/firmware_loop.cpp): one ``C`` line a clock, the inputs then the
outputs in hex, replayed through the golden model (tb/test_c_driver.py,
tb/test_firmware_loop.py)."""

from mdfqm_gateware.dropin import default_configs
from mdfqm_testkit.top_bench import make_model

NAME = "mdfqm_top_n3_w16"
OUTPUTS = ("wb_dat_r", "wb_ack", "ref_ready", "upper", "lower", "adc_trigger", "sync_out",
           "fault", "irq")


def top_params():
    """The drop-in top the harnesses run (:data:`NAME`) and its parameters, as
    :func:`mdfqm_testkit.top_bench.make_model` takes them."""
    factory = dict(default_configs(3, 16))[NAME]
    top = factory()
    return top, {k: getattr(top, k) for k in ("phases", "width", "rule", "dead_min",
                                               "upper_active_low", "lower_active_low", "bus",
                                               "counter_width", "max_bits")}


def replay_clock_log(lines, params):
    """Step a fresh golden model through the inputs of every ``C`` line of a harness log (the
    format of sw/sim/harness.cpp) and assert that every output of every clock equals the
    model's; returns the model and the number of clocks checked."""
    model = make_model(params)
    width, checked = params["width"], 0
    for line in lines:
        if not line.startswith("C "):
            continue
        f = [int(v, 16) for v in line.split()[1:]]
        cycle = int(line.split()[1])
        (rst, cyc, stb, we, adr, dat_w, sel, ref_valid, payload, fault_in, sync_in), got = \
            f[1:12], dict(zip(OUTPUTS, f[12:], strict=True))
        ref = [(payload >> (i * width)) & ((1 << width) - 1) for i in range(params["phases"])]
        out = model.step(rst=rst, ref_valid=ref_valid, ref=ref, fault_in=fault_in,
                         sync_in=sync_in, wb_cyc=cyc, wb_stb=stb, wb_we=we, wb_adr=adr,
                         wb_dat_w=dat_w, wb_sel=sel)
        want = {k: out[k] for k in OUTPUTS}
        assert got == want, f"clock {cycle}: RTL {got}, model {want}"
        checked += 1
    return model, checked
