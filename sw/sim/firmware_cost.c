/* The firmware's cost per control period, measured under valgrind (tools/drive_report.py runs
 * `valgrind --tool=callgrind --toggle-collect=mdfqm_foc_irq --toggle-collect=mdfqm_foc_adc`):
 * the two entry points of sw/foc/mdfqm_foc.c run `periods` times (argv[1]) with OSR = 4, so
 * one SAMPLE interrupt and four conversions per period, against a bus that answers as the IP
 * does to what the firmware reads (ID, INFO, IRQ_STATUS) and counts the accesses. The currents
 * and the encoder follow a rotating field so that every branch of the control law is taken
 * as in a drive. Prints the accesses per period. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "mdfqm_foc.h"

static unsigned long reads, writes;

static uint32_t bus_read(void *ctx, uint32_t offset) {
    (void)ctx;
    reads++;
    if (offset == MDFQM_TOP__ID_OFFSET)
        return MDFQM_TOP__ID__ID_reset;
    if (offset == MDFQM_TOP__INFO_OFFSET)
        return (3u << MDFQM_TOP__INFO__PHASES_bp) | (16u << MDFQM_TOP__INFO__WIDTH_bp);
    if (offset == MDFQM_TOP__IRQ_STATUS_OFFSET)
        return MDFQM_TOP__IRQ_STATUS__SAMPLE_bm;
    return 0;
}

static void bus_write(void *ctx, uint32_t offset, uint32_t value) {
    (void)ctx;
    (void)offset;
    (void)value;
    writes++;
}

int main(int argc, char **argv) {
    unsigned long periods = argc > 1 ? strtoul(argv[1], NULL, 10) : 1000;
    /* representative values (they only steer the branches the control law takes) */
    mdfqm_foc_config_t cfg = {
        .R_s = 7.125f, .L_d = 8e-3f, .L_q = 8e-3f, .psi_f = 0.0199f, .J = 3.5e-5f, .n_p = 5,
        .alpha_c = 1570.8f, .alpha_s = 157.08f, .i_max = 0.6f, .decoupling = 1,
        .delay_compensation = 1, .encoder_counts = 4096, .adc_lsb = 16.0f / 4096.0f,
        .average = 0, .f_clk = 48e6f, .period = 2400, .osr = 4, .dead = 96, .adc_offset = 1250,
        .mode = MDFQM_MODE_MDFQM};
    mdfqm_foc_t foc;
    mdfqm_bus_t bus = {bus_read, bus_write, NULL};
    if (mdfqm_foc_init(&foc, bus, &cfg, 0.0f) != 0)
        return 1;
    unsigned long init_reads = reads, init_writes = writes;
    for (unsigned long k = 0; k < periods; k++) {
        mdfqm_foc_irq(&foc);
        for (unsigned u = 0; u < cfg.osr; u++) {
            float angle = 0.01f * (float)(k * cfg.osr + u);
            int32_t adc[3];
            for (int i = 0; i < 3; i++)
                adc[i] = (int32_t)lrintf(100.0f * cosf(angle - 2.0943951f * (float)i));
            mdfqm_foc_adc(&foc, adc, (int32_t)(k * 3), 24.0f, 31.4f);
        }
    }
    printf("periods %lu reads %lu writes %lu steps %lu\n", periods,
           reads - init_reads, writes - init_writes, (unsigned long)foc.steps);
    return 0;
}
