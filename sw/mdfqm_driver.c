/* Firmware driver for the mdfqm drop-in top: see mdfqm_driver.h. */
#include "mdfqm_driver.h"

#include <stddef.h>

#define FIELD(word, reg, field) \
    (((word) & MDFQM_TOP__##reg##__##field##_bm) >> MDFQM_TOP__##reg##__##field##_bp)

static uint32_t rd(const mdfqm_t *dev, uint32_t offset)
{
    return dev->bus.read(dev->bus.ctx, offset);
}

static void wr(const mdfqm_t *dev, uint32_t offset, uint32_t value)
{
    dev->bus.write(dev->bus.ctx, offset, value);
}

static uint32_t mmio_read(void *ctx, uint32_t offset)
{
    return ((volatile uint32_t *)ctx)[offset / 4u];
}

static void mmio_write(void *ctx, uint32_t offset, uint32_t value)
{
    ((volatile uint32_t *)ctx)[offset / 4u] = value;
}

mdfqm_bus_t mdfqm_mmio_bus(volatile uint32_t *base)
{
    mdfqm_bus_t bus;
    bus.read = mmio_read;
    bus.write = mmio_write;
    bus.ctx = (void *)(uintptr_t)base;   /* the callbacks restore the volatile qualifier */
    return bus;
}

int mdfqm_init(mdfqm_t *dev, mdfqm_bus_t bus)
{
    uint32_t info;
    dev->bus = bus;
    if (rd(dev, MDFQM_TOP__ID_OFFSET) != MDFQM_TOP__ID__ID_reset)
        return -1;
    info = rd(dev, MDFQM_TOP__INFO_OFFSET);
    dev->phases = FIELD(info, INFO, PHASES);
    dev->width = FIELD(info, INFO, WIDTH);
    dev->latency = FIELD(info, INFO, LATENCY);
    dev->exact_nearest = FIELD(info, INFO, RULE) != 0u;
    dev->upper_active_low = FIELD(info, INFO, UPPER_ACTIVE_LOW) != 0u;
    dev->lower_active_low = FIELD(info, INFO, LOWER_ACTIVE_LOW) != 0u;
    dev->max_bits = FIELD(info, INFO, MAX_BITS);
    dev->modes = FIELD(info, INFO, MODES);
    dev->asc = FIELD(info, INFO, ASC) != 0u;
    dev->watchdog = FIELD(info, INFO, WATCHDOG) != 0u;
    dev->dead_min = FIELD(rd(dev, MDFQM_TOP__DEAD_MIN_OFFSET), DEAD_MIN, DEAD_MIN);
    return 0;
}

void mdfqm_set_period(const mdfqm_t *dev, uint32_t clocks)
{
    wr(dev, MDFQM_TOP__PERIOD_OFFSET, clocks);
}

void mdfqm_set_osr(const mdfqm_t *dev, uint32_t updates)
{
    wr(dev, MDFQM_TOP__OSR_OFFSET, updates);
}

void mdfqm_set_dead_time(const mdfqm_t *dev, uint32_t clocks)
{
    wr(dev, MDFQM_TOP__DEAD_OFFSET, clocks);
}

void mdfqm_set_min_pulse(const mdfqm_t *dev, uint32_t clocks)
{
    wr(dev, MDFQM_TOP__MIN_PULSE_OFFSET, clocks);
}

void mdfqm_set_adc_offset(const mdfqm_t *dev, uint32_t clocks)
{
    wr(dev, MDFQM_TOP__ADC_OFFSET_OFFSET, clocks);
}

/* CTRL holds two settings: read-modify-write keeps the other. */
static void ctrl_set(const mdfqm_t *dev, uint32_t mask, bool on)
{
    uint32_t ctrl = rd(dev, MDFQM_TOP__CTRL_OFFSET);
    wr(dev, MDFQM_TOP__CTRL_OFFSET, on ? (ctrl | mask) : (ctrl & ~mask));
}

void mdfqm_set_zero_policy(const mdfqm_t *dev, bool fewer_transitions)
{
    ctrl_set(dev, MDFQM_TOP__CTRL__ZERO_POLICY_bm, fewer_transitions);
}

void mdfqm_enable(const mdfqm_t *dev, bool on)
{
    ctrl_set(dev, MDFQM_TOP__CTRL__ENABLE_bm, on);
}

void mdfqm_write_reference(const mdfqm_t *dev, const int32_t *codes)
{
    unsigned i;
    for (i = 0; i < dev->phases; i++)
        wr(dev, MDFQM_TOP__REF_OFFSET(i), (uint32_t)codes[i]);
    wr(dev, MDFQM_TOP__CMD_OFFSET, MDFQM_TOP__CMD__REF_COMMIT_bm);
}

uint32_t mdfqm_status(const mdfqm_t *dev)
{
    return rd(dev, MDFQM_TOP__STATUS_OFFSET);
}

uint32_t mdfqm_events(const mdfqm_t *dev, unsigned leg)
{
    return rd(dev, MDFQM_TOP__EVENTS_OFFSET(leg));
}

uint32_t mdfqm_events_total(const mdfqm_t *dev)
{
    return rd(dev, MDFQM_TOP__EVENTS_TOTAL_OFFSET);
}

void mdfqm_clear_counters(const mdfqm_t *dev)
{
    wr(dev, MDFQM_TOP__CMD_OFFSET, MDFQM_TOP__CMD__COUNT_CLEAR_bm);
}

bool mdfqm_clear_fault(const mdfqm_t *dev)
{
    wr(dev, MDFQM_TOP__CMD_OFFSET, MDFQM_TOP__CMD__FAULT_CLEAR_bm);
    return FIELD(mdfqm_status(dev), STATUS, FAULT) == 0u;
}

void mdfqm_set_modulation(const mdfqm_t *dev, unsigned mode, unsigned bits)
{
    wr(dev, MDFQM_TOP__MODULATION_OFFSET,
       (((uint32_t)mode << MDFQM_TOP__MODULATION__MODE_bp) & MDFQM_TOP__MODULATION__MODE_bm)
       | (((uint32_t)bits << MDFQM_TOP__MODULATION__BITS_bp) & MDFQM_TOP__MODULATION__BITS_bm));
}

void mdfqm_modulation_in_force(const mdfqm_t *dev, unsigned *mode, unsigned *bits)
{
    uint32_t word = rd(dev, MDFQM_TOP__MODULATION_OFFSET);
    *mode = FIELD(word, MODULATION, MODE);
    *bits = FIELD(word, MODULATION, BITS);
}

void mdfqm_set_watchdog(const mdfqm_t *dev, uint32_t updates)
{
    wr(dev, MDFQM_TOP__WATCHDOG_OFFSET, updates);
}

void mdfqm_clear_watchdog(const mdfqm_t *dev)
{
    wr(dev, MDFQM_TOP__CMD_OFFSET, MDFQM_TOP__CMD__WATCHDOG_CLEAR_bm);
}

uint32_t mdfqm_watchdog_trips(const mdfqm_t *dev)
{
    return rd(dev, MDFQM_TOP__WATCHDOG_TRIPS_OFFSET);
}

void mdfqm_set_fault_reaction(const mdfqm_t *dev, mdfqm_source_t source,
                              mdfqm_reaction_t reaction)
{
    uint32_t word = rd(dev, MDFQM_TOP__FAULT_REACTION_OFFSET);
    uint32_t code = (uint32_t)reaction;
    if (source == MDFQM_SOURCE_WATCHDOG)
        word = (word & ~(uint32_t)MDFQM_TOP__FAULT_REACTION__WATCHDOG_bm)
               | ((code << MDFQM_TOP__FAULT_REACTION__WATCHDOG_bp)
                  & MDFQM_TOP__FAULT_REACTION__WATCHDOG_bm);
    else
        word = (word & ~(uint32_t)MDFQM_TOP__FAULT_REACTION__FAULT_bm)
               | ((code << MDFQM_TOP__FAULT_REACTION__FAULT_bp)
                  & MDFQM_TOP__FAULT_REACTION__FAULT_bm);
    wr(dev, MDFQM_TOP__FAULT_REACTION_OFFSET, word);
}

void mdfqm_fault_all_off(const mdfqm_t *dev)
{
    wr(dev, MDFQM_TOP__CMD_OFFSET, MDFQM_TOP__CMD__ALL_OFF_bm);
}

mdfqm_reaction_t mdfqm_reaction_in_force(const mdfqm_t *dev)
{
    switch (FIELD(mdfqm_status(dev), STATUS, REACTION)) {
    case 1u:
        return MDFQM_REACTION_ASC_LOW;
    case 2u:
        return MDFQM_REACTION_ASC_HIGH;
    default:
        return MDFQM_REACTION_ALL_OFF;
    }
}

void mdfqm_irq_enable(const mdfqm_t *dev, uint32_t sources)
{
    wr(dev, MDFQM_TOP__IRQ_ENABLE_OFFSET, sources);
}

mdfqm_irq_causes_t mdfqm_irq_handle(const mdfqm_t *dev)
{
    mdfqm_irq_causes_t causes;
    uint32_t status = rd(dev, MDFQM_TOP__IRQ_STATUS_OFFSET);
    wr(dev, MDFQM_TOP__IRQ_STATUS_OFFSET, status);
    causes.fault = FIELD(status, IRQ_STATUS, FAULT) != 0u;
    causes.counter_wrap = FIELD(status, IRQ_STATUS, COUNTER_WRAP) != 0u;
    causes.sample = FIELD(status, IRQ_STATUS, SAMPLE) != 0u;
    causes.short_edge = FIELD(status, IRQ_STATUS, SHORT_EDGE) != 0u;
    causes.watchdog = FIELD(status, IRQ_STATUS, WATCHDOG) != 0u;
    return causes;
}
