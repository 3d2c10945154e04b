/* Speed-controlled FOC of a PMSM on the mdfqm IP: the firmware example of docs/drive.md.
 *
 * Portable C99 in single-precision float (as a Cortex-M4F or a soft CPU with an FPU runs it), no
 * allocation, no platform headers: the IP is reached only through the C driver
 * (sw/mdfqm_driver.h) and so only through the register header generated from the SystemRDL map.
 * The control law is drive/mdfqm_drive/control.py's FocController line for line (speed I-P,
 * IMC current PIs with decoupling and back-calculation anti-windup, the linear-range voltage
 * limit, delay compensation, the encoder tracking loop): the Python model path and this
 * firmware are two implementations of one set of difference equations.
 *
 * Two entry points, as on a microcontroller:
 *  - mdfqm_foc_irq() on the IP's irq line: the SAMPLE interrupt starts a control period (the
 *    IP has just taken the last reference); a FAULT stops the control law (the IP's fault
 *    reaction holds the gates), WATCHDOG is counted;
 *  - mdfqm_foc_adc() when the phase-current ADC, started by the IP's adc_trigger pin, has
 *    converted: the sample is kept; the first conversion after a SAMPLE interrupt runs the
 *    control law and writes the next reference, which the IP takes at its next sampling tick
 *    (one control period of computation delay).
 */
#ifndef MDFQM_FOC_H
#define MDFQM_FOC_H

#include <stdbool.h>
#include <stdint.h>

#include "mdfqm_driver.h"

#ifdef __cplusplus
extern "C" {
#endif

#define MDFQM_FOC_MAX_OSR 16u

/* Everything the firmware is built with: the motor, the tuning, the sensors and the IP's
 * settings. Plain 32-bit fields (no bool) so that a simulation can fill it from another
 * language without layout questions. */
typedef struct {
    /* the motor (SI units) and the shaft's inertia as the speed loop assumes it */
    float R_s, L_d, L_q, psi_f, J;
    uint32_t n_p;
    /* tuning: current- and speed-loop bandwidths (rad/s), current limit (A) */
    float alpha_c, alpha_s, i_max;
    uint32_t decoupling, delay_compensation;
    /* sensors: encoder counts per mechanical revolution, amps per ADC code; average: control
     * from the mean of the last OSR per-update samples instead of the period's one sample */
    uint32_t encoder_counts;
    float adc_lsb;
    uint32_t average;
    /* the IP: clock (Hz) and the registers the firmware sets */
    float f_clk;
    uint32_t period, osr, dead, min_pulse, adc_offset, mode, bits, fewest_transitions;
    /* the reaction to the fault pin (mdfqm_reaction_t: all off, ASC low, ASC high), and the
     * speed (rad/s) below which the firmware ends an active short circuit (CMD.ALL_OFF);
     * 0: it never does */
    uint32_t fault_reaction;
    float asc_exit_speed;
} mdfqm_foc_config_t;

typedef struct {
    mdfqm_t dev;
    mdfqm_foc_config_t cfg;
    /* derived once at init */
    float T_c, kp_d, kp_q, ki, ks_p, ks_i, tau_max, ko_p, ko_i, k_t, scale_full;
    /* controller state */
    float int_d, int_q, int_s, w_hat, theta_hat_rel;
    int32_t count_base;
    bool tracking;
    float i_alpha, i_beta;               /* the last valid current measurement (A) */
    int32_t ring[MDFQM_FOC_MAX_OSR][3];  /* the last OSR samples (ADC codes) */
    unsigned ring_fill, ring_next;
    bool period_started;
    /* what the last control step computed (for a debugger or a trace) */
    float i_q_ref, i_d_meas, i_q_meas;
    int32_t codes[3];
    /* a fault seen: the control law stops, the speed is still tracked */
    bool faulted, all_off_sent;
    /* bookkeeping */
    uint32_t periods, steps, missed, faults, watchdogs;
} mdfqm_foc_t;

/* Identifies the IP, programs PERIOD, OSR, DEAD, MIN_PULSE, ADC_OFFSET, MODULATION, the zero
 * policy, the fault pin's reaction and the interrupts (SAMPLE, FAULT, WATCHDOG), and enables
 * the gates. The speed
 * estimate starts at w_m0 (rad/s). Returns 0, or -1 (not an mdfqm IP; a three-phase IP with
 * width >= 4 needed; osr above MDFQM_FOC_MAX_OSR). */
int mdfqm_foc_init(mdfqm_foc_t *foc, mdfqm_bus_t bus, const mdfqm_foc_config_t *cfg,
                   float w_m0);

/* The IP's irq line is high: serve and acknowledge it. */
void mdfqm_foc_irq(mdfqm_foc_t *foc);

/* A conversion is complete: adc[3] the phase-current codes (signed, adc_lsb amps each),
 * encoder_count the encoder latched with it, u_dc the bus voltage (V), w_ref the speed
 * reference (rad/s). Returns true when it ran the control law and wrote a reference. After a
 * fault it only tracks the speed, once per control period, and ends an active short circuit
 * below asc_exit_speed. */
bool mdfqm_foc_adc(mdfqm_foc_t *foc, const int32_t adc[3], int32_t encoder_count, float u_dc,
                   float w_ref);

#ifdef __cplusplus
}
#endif

#endif /* MDFQM_FOC_H */
