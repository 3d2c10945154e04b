/* Firmware driver for the mdfqm drop-in top (MdfqmTop, Wishbone or AXI4-Lite front).
 *
 * Portable C99, no allocation, no platform headers: every register access goes through the two
 * callbacks of mdfqm_bus_t, so the same code runs on memory-mapped hardware (mdfqm_mmio_bus)
 * and in a simulation harness (sw/sim/harness.cpp). Register offsets and fields come only from
 * the header generated from the SystemRDL map (build/generated/mdfqm_top_regs.h).
 */
#ifndef MDFQM_DRIVER_H
#define MDFQM_DRIVER_H

#include <stdbool.h>
#include <stdint.h>

#include "mdfqm_top_regs.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Byte-offset register access; ctx is the caller's (a base address, a simulator handle). */
typedef struct {
    uint32_t (*read)(void *ctx, uint32_t offset);
    void (*write)(void *ctx, uint32_t offset, uint32_t value);
    void *ctx;
} mdfqm_bus_t;

/* One instance: its bus and the elaboration parameters read from INFO and DEAD_MIN. */
typedef struct {
    mdfqm_bus_t bus;
    unsigned phases;
    unsigned width;          /* reference code width: codes in [-2**(width-1), 2**(width-1)-1] */
    unsigned latency;        /* loop latency L: PERIOD below it is raised to it */
    unsigned dead_min;       /* dead-time floor in clocks */
    bool exact_nearest;      /* rule: 0 largest_duty, 1 exact_nearest */
    bool upper_active_low;
    bool lower_active_low;
    unsigned max_bits;       /* largest b of the slot modes; 0: the MDFQM-only top */
    unsigned modes;          /* modulation modes built in: MODULATION.MODE codes 0..modes-1 */
    bool asc;                /* the active short circuit built in (INFO.ASC) */
    bool watchdog;           /* the reference watchdog built in (INFO.WATCHDOG) */
} mdfqm_t;

/* What the interrupt handler found (and acknowledged). */
typedef struct {
    bool fault;              /* the fault latch set: the fault reaction until mdfqm_clear_fault */
    bool counter_wrap;       /* EVENTS_TOTAL wrapped */
    bool sample;             /* a sampling tick: write the next reference now */
    bool short_edge;         /* a pulse shorter than dead time + minimum pulse was swallowed or
                                stretched (a slot or an update too short for the settings) */
    bool watchdog;           /* the reference watchdog tripped: the fault reaction until
                                mdfqm_clear_watchdog */
} mdfqm_irq_causes_t;

/* The sources of a fault reaction and the reactions (FAULT_REACTION's fields and codes;
 * docs/top.md, "Fault reaction"). */
typedef enum { MDFQM_SOURCE_FAULT = 0, MDFQM_SOURCE_WATCHDOG = 1 } mdfqm_source_t;
typedef enum {
    MDFQM_REACTION_ALL_OFF = 0,     /* every switch off (the reset value) */
    MDFQM_REACTION_ASC_LOW = 1,     /* active short circuit: the lower switches on */
    MDFQM_REACTION_ASC_HIGH = 2     /* active short circuit: the upper switches on (needs the
                                       upper gate supplies to stay up) */
} mdfqm_reaction_t;

/* MODULATION.MODE codes (docs/top.md, "Modulation mode and resolution"). */
enum { MDFQM_MODE_MDFQM = 0, MDFQM_MODE_SVPWM = 1, MDFQM_MODE_DPWM0 = 2, MDFQM_MODE_DPWM1 = 3,
       MDFQM_MODE_DPWM = 4 };

/* An mdfqm_bus_t for a memory-mapped instance at base (volatile 32-bit accesses). */
mdfqm_bus_t mdfqm_mmio_bus(volatile uint32_t *base);

/* Checks ID, reads INFO and DEAD_MIN. Returns 0, or -1 if ID is not "MDFQ" (wrong address). */
int mdfqm_init(mdfqm_t *dev, mdfqm_bus_t bus);

/* Runtime settings, each clamped by the IP as docs/top.md says (PERIOD >= latency, DEAD >=
 * dead_min, 16-bit saturation). The enable is taken at the next update boundary. */
void mdfqm_set_period(const mdfqm_t *dev, uint32_t clocks);
void mdfqm_set_osr(const mdfqm_t *dev, uint32_t updates);
void mdfqm_set_dead_time(const mdfqm_t *dev, uint32_t clocks);
void mdfqm_set_min_pulse(const mdfqm_t *dev, uint32_t clocks);
void mdfqm_set_adc_offset(const mdfqm_t *dev, uint32_t clocks);
/* The core's zero-vector policy (CTRL.ZERO_POLICY): false all-off, true fewer transitions. */
void mdfqm_set_zero_policy(const mdfqm_t *dev, bool fewer_transitions);
/* Request a modulation mode and resolution b (2**b slots per update in the slot modes); the
 * next update start takes them, clamped (a mode not built in acts as MDFQM, b to [1, max_bits];
 * STATUS.MODE_CLAMPED flags that update). */
void mdfqm_set_modulation(const mdfqm_t *dev, unsigned mode, unsigned bits);
/* The mode and b in force (those of the last update start, after the clamp). */
void mdfqm_modulation_in_force(const mdfqm_t *dev, unsigned *mode, unsigned *bits);
void mdfqm_enable(const mdfqm_t *dev, bool on);

/* Writes REF[0..phases-1] (saturated by the IP to the code range) and commits them as one
 * beat: the core takes them at its next sampling tick. */
void mdfqm_write_reference(const mdfqm_t *dev, const int32_t *codes);

uint32_t mdfqm_status(const mdfqm_t *dev);
uint32_t mdfqm_events(const mdfqm_t *dev, unsigned leg);
uint32_t mdfqm_events_total(const mdfqm_t *dev);
void mdfqm_clear_counters(const mdfqm_t *dev);
/* Clears the fault latch; it stays set while the fault input is still active. Returns whether
 * the latch is clear afterwards. Gates resume at the next update boundary with the enable. */
bool mdfqm_clear_fault(const mdfqm_t *dev);

/* The reference watchdog (docs/top.md, "Reference watchdog"): 0 turns it off (the reset value);
 * otherwise the update starts allowed without a new reference (a beat on the ref port or a
 * mdfqm_write_reference), saturated at 65535. The next start without one starts the watchdog's
 * fault reaction (every gate off by default) until mdfqm_clear_watchdog. Without the watchdog
 * built in (dev->watchdog false) the write stores 0: it never trips. */
void mdfqm_set_watchdog(const mdfqm_t *dev, uint32_t updates);
/* Clears the watchdog latch (gates resume at the next update boundary with the enable). */
void mdfqm_clear_watchdog(const mdfqm_t *dev);
/* Trips since reset or mdfqm_clear_counters (saturating at 65535). */
uint32_t mdfqm_watchdog_trips(const mdfqm_t *dev);

/* The reaction to one source's latch (read-modify-write of FAULT_REACTION, the other source's
 * reaction kept). Used the next time the gates leave normal operation: never changes a
 * reaction in force. Without the ASC built in (dev->asc false) every reaction is all off. */
void mdfqm_set_fault_reaction(const mdfqm_t *dev, mdfqm_source_t source,
                              mdfqm_reaction_t reaction);
/* CMD.ALL_OFF: an active short circuit in force ends, every switch off from the clock after the
 * register file takes the write (two clocks after the bus request; the latches stay set: clear
 * them as usual). Firmware's step from ASC to all off once the
 * speed is below the back-EMF threshold. */
void mdfqm_fault_all_off(const mdfqm_t *dev);
/* STATUS.REACTION: the reaction in force (all off also when no latch is set). */
mdfqm_reaction_t mdfqm_reaction_in_force(const mdfqm_t *dev);

/* IRQ_ENABLE sources (MDFQM_TOP__IRQ_ENABLE__*_bm). */
void mdfqm_irq_enable(const mdfqm_t *dev, uint32_t sources);
/* Call on the irq line: reads IRQ_STATUS, acknowledges exactly the bits it read (write 1 to
 * clear; an event arriving meanwhile stays set and raises irq again), returns the causes. */
mdfqm_irq_causes_t mdfqm_irq_handle(const mdfqm_t *dev);

#ifdef __cplusplus
}
#endif

#endif /* MDFQM_DRIVER_H */
