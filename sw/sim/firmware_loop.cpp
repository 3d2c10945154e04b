// Firmware in the loop: the FOC firmware (sw/foc/mdfqm_foc.c) on the C driver, programming the
// Verilated drop-in top mdfqm_top_n3_w16 through a Wishbone shim, as a shared library that
// drive/mdfqm_drive/firmware_loop.py loads with ctypes and closes around the motor model.
//
// The library runs clocks and records what the plant needs: every change of the gate pins
// (cycle, upper, lower: the pins hold from that cycle on) and every adc_trigger pulse. It
// returns to Python at each trigger; Python advances the motor through the recorded edges to
// the trigger's cycle, samples it, and hands the conversion to the firmware (fil_adc). The
// firmware's interrupt handler runs whenever the top's irq line is high between bus accesses.
// A bus access takes the clocks of a classic Wishbone cycle plus one idle clock; the firmware's
// arithmetic takes none (its cost is measured apart: docs/drive.md).
//
// Timing as sw/sim/harness.cpp: the inputs of a clock are set after the rising edge that
// starts it, the outputs read with the clock low, before the edge that ends it. With a log
// path, the first log_clocks clocks are written in harness.cpp's "C" line format for the
// clock-by-clock comparison with the golden model.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <vector>

#include "Vmdfqm_top_n3_w16.h"
#include "verilated.h"

#include "mdfqm_foc.h"

namespace {

struct Edge {
    uint64_t cycle;
    uint32_t upper, lower;
};

struct Loop {
    VerilatedContext context;
    Vmdfqm_top_n3_w16 top{&context};
    uint64_t cycle = 0;
    std::vector<Edge> edges;
    std::deque<uint64_t> triggers;
    uint32_t upper = 0, lower = 0;
    uint64_t first_sync = 0;
    bool synced = false;
    FILE *log = nullptr;
    uint64_t log_clocks = 0;
    uint64_t bus_reads = 0, bus_writes = 0, bus_clocks = 0, irqs = 0;
    unsigned ack = 0;
    uint32_t dat_r = 0;
    mdfqm_foc_t foc;

    void clock() {
        top.clk = 0;
        top.eval();
        if (log != nullptr && cycle < log_clocks)
            std::fprintf(log,
                         "C %llu %x %x %x %x %x %x %x %x %llx %x %x %x %x %x %x %x %x %x %x %x\n",
                         (unsigned long long)cycle, top.rst, top.wb___05Fcyc, top.wb___05Fstb,
                         top.wb___05Fwe, top.wb___05Fadr, top.wb___05Fdat_w, top.wb___05Fsel,
                         top.ref___05Fvalid, (unsigned long long)top.ref___05Fpayload,
                         top.fault_in, top.sync_in, top.wb___05Fdat_r, top.wb___05Fack,
                         top.ref___05Fready, top.upper, top.lower, top.adc_trigger,
                         top.sync_out, top.fault, top.irq);
        ack = top.wb___05Fack;
        dat_r = top.wb___05Fdat_r;
        if (top.upper != upper || top.lower != lower) {
            upper = top.upper;
            lower = top.lower;
            edges.push_back({cycle, upper, lower});
        }
        if (top.adc_trigger)
            triggers.push_back(cycle);
        if (top.sync_out && !synced && top.rst == 0) {
            synced = true;
            first_sync = cycle;
        }
        top.clk = 1;
        top.eval();
        cycle++;
    }

    void idle() {
        top.wb___05Fcyc = 0;
        top.wb___05Fstb = 0;
        top.wb___05Fwe = 0;
        clock();
    }

    uint32_t access(uint32_t offset, int we, uint32_t value) {
        uint64_t start = cycle;
        top.wb___05Fcyc = 1;
        top.wb___05Fstb = 1;
        top.wb___05Fwe = we;
        top.wb___05Fadr = offset / 4u;
        top.wb___05Fdat_w = value;
        top.wb___05Fsel = 0xF;
        for (int wait = 0;; wait++) {
            clock();
            if (ack)
                break;
            if (wait > 100) {
                std::fprintf(stderr, "firmware_loop: no ack at offset 0x%x\n", offset);
                std::abort();
            }
        }
        uint32_t got = dat_r;
        idle();
        bus_clocks += cycle - start;
        return got;
    }
};

uint32_t bus_read(void *ctx, uint32_t offset) {
    Loop *loop = static_cast<Loop *>(ctx);
    loop->bus_reads++;
    return loop->access(offset, 0, 0);
}

void bus_write(void *ctx, uint32_t offset, uint32_t value) {
    Loop *loop = static_cast<Loop *>(ctx);
    loop->bus_writes++;
    loop->access(offset, 1, value);
}

}  // namespace

extern "C" {

// A reset top (two clocks of rst), the log opened when log_path is not null.
void *fil_new(const char *log_path, uint64_t log_clocks) {
    Loop *loop = new Loop;
    if (log_path != nullptr && log_clocks > 0) {
        loop->log = std::fopen(log_path, "w");
        loop->log_clocks = log_clocks;
    }
    Vmdfqm_top_n3_w16 &top = loop->top;
    top.ref___05Fvalid = 0;
    top.ref___05Fpayload = 0;
    top.sync_in = 0;
    top.fault_in = 0;
    top.rst = 1;
    loop->idle();
    loop->idle();
    top.rst = 0;
    return loop;
}

void fil_free(void *handle) {
    Loop *loop = static_cast<Loop *>(handle);
    if (loop->log != nullptr)
        std::fclose(loop->log);
    loop->top.final();
    delete loop;
}

// The firmware's initialisation (it programs and enables the IP). Returns its result.
int fil_init(void *handle, const mdfqm_foc_config_t *cfg, float w_m0) {
    Loop *loop = static_cast<Loop *>(handle);
    mdfqm_bus_t bus = {bus_read, bus_write, loop};
    return mdfqm_foc_init(&loop->foc, bus, cfg, w_m0);
}

// Runs clocks up to cycle `until`, serving interrupts; returns 1 at an ADC trigger (its cycle
// in *trigger), 0 once `until` is reached.
int fil_run(void *handle, uint64_t until, uint64_t *trigger) {
    Loop *loop = static_cast<Loop *>(handle);
    for (;;) {
        if (!loop->triggers.empty()) {
            *trigger = loop->triggers.front();
            loop->triggers.pop_front();
            return 1;
        }
        if (loop->cycle >= until)
            return 0;
        if (loop->top.irq) {
            loop->irqs++;
            mdfqm_foc_irq(&loop->foc);
        } else {
            loop->idle();
        }
    }
}

// Moves up to `room` recorded pin changes out; returns how many.
size_t fil_edges(void *handle, uint64_t *cycles, uint32_t *upper, uint32_t *lower, size_t room) {
    Loop *loop = static_cast<Loop *>(handle);
    size_t n = loop->edges.size() < room ? loop->edges.size() : room;
    for (size_t k = 0; k < n; k++) {
        cycles[k] = loop->edges[k].cycle;
        upper[k] = loop->edges[k].upper;
        lower[k] = loop->edges[k].lower;
    }
    loop->edges.erase(loop->edges.begin(), loop->edges.begin() + (long)n);
    return n;
}

// The conversion of the last trigger, to the firmware; returns 1 when it wrote a reference.
int fil_adc(void *handle, const int32_t *adc, int32_t encoder_count, float u_dc, float w_ref) {
    Loop *loop = static_cast<Loop *>(handle);
    return mdfqm_foc_adc(&loop->foc, adc, encoder_count, u_dc, w_ref) ? 1 : 0;
}

// What the firmware's last control step computed: w_hat, i_q_ref, i_d, i_q; and its codes.
void fil_outputs(void *handle, float *values, int32_t *codes) {
    const mdfqm_foc_t &foc = static_cast<Loop *>(handle)->foc;
    values[0] = foc.w_hat;
    values[1] = foc.i_q_ref;
    values[2] = foc.i_d_meas;
    values[3] = foc.i_q_meas;
    for (int i = 0; i < 3; i++)
        codes[i] = foc.codes[i];
}

// The fault input from the next clock on.
void fil_set_fault(void *handle, int level) {
    static_cast<Loop *>(handle)->top.fault_in = level ? 1 : 0;
}

// Counters: cycle, first update start, bus reads, bus writes, clocks in bus accesses,
// interrupts served, firmware periods, control steps, missed periods, faults, watchdogs, and
// whether the firmware ended an active short circuit.
void fil_counters(void *handle, uint64_t *out) {
    const Loop *loop = static_cast<Loop *>(handle);
    const mdfqm_foc_t &foc = loop->foc;
    uint64_t values[] = {loop->cycle, loop->first_sync, loop->bus_reads, loop->bus_writes,
                         loop->bus_clocks, loop->irqs, foc.periods, foc.steps, foc.missed,
                         foc.faults, foc.watchdogs, foc.all_off_sent ? 1u : 0u};
    for (size_t k = 0; k < sizeof values / sizeof values[0]; k++)
        out[k] = values[k];
}

}  // extern "C"
