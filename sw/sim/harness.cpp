// Runs the C driver (sw/mdfqm_driver.c) against the Verilated drop-in top mdfqm_top_n3_w16,
// through a Wishbone shim, as firmware would on a CPU: init, timing, interrupt-driven reference
// updates, a fault with an active short circuit low as its reaction, CMD.ALL_OFF, the clear,
// counters. Every clock it logs the top's inputs and outputs,
// and each driver result; tb/test_c_driver.py replays the inputs through the golden model and
// compares every output of every clock, then checks the driver's results.
//
// Timing as tb/harness.check_cycles: the inputs of a clock are set after the rising edge that
// starts it, the outputs are read with the clock low, before the edge that ends it.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>

#include "Vmdfqm_top_n3_w16.h"
#include "verilated.h"

#include "mdfqm_driver.h"

// Verilator spells the "__" of a port name as "___05F"

namespace {

struct Sim {
    Vmdfqm_top_n3_w16 *top;
    FILE *log;
    unsigned long cycle = 0;
    int fault_in = 0;

    // one clock with the inputs as set now; logs them and the outputs
    void clock() {
        top->fault_in = fault_in;
        top->clk = 0;
        top->eval();
        std::fprintf(log, "C %lu %x %x %x %x %x %x %x %x %llx %x %x %x %x %x %x %x %x %x %x %x\n",
                     cycle, top->rst, top->wb___05Fcyc, top->wb___05Fstb, top->wb___05Fwe,
                     top->wb___05Fadr, top->wb___05Fdat_w, top->wb___05Fsel, top->ref___05Fvalid,
                     (unsigned long long)top->ref___05Fpayload, top->fault_in, top->sync_in,
                     top->wb___05Fdat_r, top->wb___05Fack, top->ref___05Fready, top->upper,
                     top->lower, top->adc_trigger, top->sync_out, top->fault, top->irq);
        ack = top->wb___05Fack;
        dat_r = top->wb___05Fdat_r;
        top->clk = 1;
        top->eval();
        cycle++;
    }
    unsigned ack = 0;
    uint32_t dat_r = 0;

    void idle() {
        top->wb___05Fcyc = 0;
        top->wb___05Fstb = 0;
        top->wb___05Fwe = 0;
        clock();
    }

    // one classic Wishbone access, then one idle clock
    uint32_t access(uint32_t offset, int we, uint32_t value) {
        top->wb___05Fcyc = 1;
        top->wb___05Fstb = 1;
        top->wb___05Fwe = we;
        top->wb___05Fadr = offset / 4u;
        top->wb___05Fdat_w = value;
        top->wb___05Fsel = 0xF;
        for (int wait = 0;; wait++) {
            clock();
            if (ack) break;
            if (wait > 100) {
                std::fprintf(stderr, "no ack at offset 0x%x\n", offset);
                std::exit(2);
            }
        }
        uint32_t got = dat_r;
        idle();
        return got;
    }
};

uint32_t bus_read(void *ctx, uint32_t offset) {
    Sim *sim = static_cast<Sim *>(ctx);
    uint32_t value = sim->access(offset, 0, 0);
    std::fprintf(sim->log, "READ %x %x\n", offset, value);
    return value;
}

void bus_write(void *ctx, uint32_t offset, uint32_t value) {
    static_cast<Sim *>(ctx)->access(offset, 1, value);
}

}  // namespace

int main(int argc, char **argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: %s LOG\n", argv[0]);
        return 2;
    }
    VerilatedContext context;
    Vmdfqm_top_n3_w16 top{&context};
    Sim sim{&top, std::fopen(argv[1], "w")};
    top.ref___05Fvalid = 0;
    top.ref___05Fpayload = 0;
    top.sync_in = 0;
    top.rst = 1;
    sim.idle();
    sim.idle();
    top.rst = 0;

    mdfqm_t dev;
    mdfqm_bus_t bus = {bus_read, bus_write, &sim};
    int ok = mdfqm_init(&dev, bus);
    std::fprintf(sim.log, "INIT %d %u %u %u %u %u %u %d %d\n", ok, dev.phases, dev.width,
                 dev.latency, dev.dead_min, dev.max_bits, dev.modes, dev.asc, dev.watchdog);
    // a motor above the back-EMF threshold: the fault pin's reaction is ASC low, the watchdog's
    // stays all off
    mdfqm_set_fault_reaction(&dev, MDFQM_SOURCE_FAULT, MDFQM_REACTION_ASC_LOW);
    mdfqm_set_period(&dev, 60);
    mdfqm_set_osr(&dev, 2);
    mdfqm_set_dead_time(&dev, 70);
    mdfqm_set_min_pulse(&dev, 3);
    mdfqm_set_adc_offset(&dev, 5);
    mdfqm_set_zero_policy(&dev, true);
    mdfqm_irq_enable(&dev, MDFQM_TOP__IRQ_ENABLE__FAULT_bm | MDFQM_TOP__IRQ_ENABLE__SAMPLE_bm
                               | MDFQM_TOP__IRQ_ENABLE__WATCHDOG_bm);
    mdfqm_set_watchdog(&dev, 6);    // a reference every OSR = 2 updates: three missed trip it
    mdfqm_enable(&dev, true);

    // firmware: on each sampling tick, the next point of a rotating voltage vector
    const double full = std::ldexp(1.0, (int)dev.width - 2);
    double angle = 0.0;
    unsigned samples = 0, faults = 0, skipped = 0, watchdogs = 0;
    bool fault_pending_clear = false, switched = false, watchdog_pending_clear = false;
    bool asc_ended = false;
    for (unsigned long t = 0; sim.cycle < 40000; t++) {
        if (!switched && sim.cycle >= 10000 && dev.max_bits >= 3) {
            mdfqm_set_modulation(&dev, MDFQM_MODE_SVPWM, 3);   // SVPWM at b = 3 from here on
            switched = true;
            continue;
        }
        sim.fault_in = (sim.cycle >= 20000 && sim.cycle < 20006);
        if (top.irq) {
            mdfqm_irq_causes_t causes = mdfqm_irq_handle(&dev);
            std::fprintf(sim.log, "IRQ %d %d %d %d\n", causes.fault, causes.counter_wrap,
                         causes.sample, causes.watchdog);
            if (causes.fault) {
                faults++;
                fault_pending_clear = true;
            }
            if (causes.watchdog) {
                watchdogs++;
                watchdog_pending_clear = true;
            }
            // a stalled control loop: the ticks are acknowledged, no reference is written
            bool stalled = sim.cycle >= 30000 && sim.cycle < 32000;
            if (causes.sample && stalled) {
                skipped++;
            } else if (causes.sample) {
                int32_t codes[16];
                angle += 0.05;
                for (unsigned i = 0; i < dev.phases; i++)
                    codes[i] = (int32_t)std::lround(
                        0.55 * full * std::cos(angle - 2.0 * 3.14159265358979323846 * i / dev.phases));
                mdfqm_write_reference(&dev, codes);
                samples++;
            }
        } else if (watchdog_pending_clear && sim.cycle > 32000) {
            mdfqm_clear_watchdog(&dev);
            std::fprintf(sim.log, "WATCHDOG_CLEAR\n");
            watchdog_pending_clear = false;
        } else if (fault_pending_clear && !asc_ended && sim.cycle > 20500) {
            // the speed has fallen below the threshold: from ASC to all off, the latch kept
            mdfqm_reaction_t before = mdfqm_reaction_in_force(&dev);
            mdfqm_fault_all_off(&dev);
            mdfqm_reaction_t after = mdfqm_reaction_in_force(&dev);
            std::fprintf(sim.log, "ASC %d %d\n", (int)before, (int)after);
            asc_ended = true;
        } else if (fault_pending_clear && sim.cycle > 21000) {
            bool clear = mdfqm_clear_fault(&dev);
            std::fprintf(sim.log, "CLEAR %d\n", clear);
            fault_pending_clear = !clear;
        } else {
            sim.idle();
        }
    }
    // (each read logs its clocks: read everything before printing a line)
    uint32_t counts[17];
    for (unsigned i = 0; i < dev.phases; i++)
        counts[i] = mdfqm_events(&dev, i);
    counts[dev.phases] = mdfqm_events_total(&dev);
    std::fprintf(sim.log, "COUNTS");
    for (unsigned i = 0; i <= dev.phases; i++)
        std::fprintf(sim.log, " %x", counts[i]);
    std::fprintf(sim.log, "\n");
    mdfqm_clear_counters(&dev);
    uint32_t total = mdfqm_events_total(&dev), status = mdfqm_status(&dev);
    std::fprintf(sim.log, "CLEARED %x %x\n", total, status);
    uint32_t trips = mdfqm_watchdog_trips(&dev);   // zeroed by the clear above
    unsigned mode, bits;
    mdfqm_modulation_in_force(&dev, &mode, &bits);
    std::fprintf(sim.log, "MODULATION %u %u\n", mode, bits);
    std::fprintf(sim.log, "DONE %u %u %u %u %u\n", samples, faults, skipped, watchdogs,
                 (unsigned)trips);
    std::fclose(sim.log);
    top.final();
    return 0;
}
