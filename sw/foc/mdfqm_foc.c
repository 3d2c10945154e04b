/* Speed-controlled FOC on the mdfqm IP (see mdfqm_foc.h). */
#include "mdfqm_foc.h"

#include <math.h>

#define TWO_PI 6.28318530718f
#define SQRT3 1.73205080757f
#define LINEAR_RANGE 0.57735026919f /* 1 / sqrt(3): the largest circle inside the hexagon */

int mdfqm_foc_init(mdfqm_foc_t *foc, mdfqm_bus_t bus, const mdfqm_foc_config_t *cfg,
                   float w_m0) {
    mdfqm_foc_t zero = {0};
    *foc = zero;
    foc->cfg = *cfg;
    if (mdfqm_init(&foc->dev, bus) != 0 || foc->dev.phases != 3 || foc->dev.width < 4
        || cfg->osr < 1 || cfg->osr > MDFQM_FOC_MAX_OSR)
        return -1;
    const mdfqm_t *dev = &foc->dev;
    foc->T_c = (float)cfg->osr * (float)cfg->period / cfg->f_clk;
    foc->kp_d = cfg->alpha_c * cfg->L_d;
    foc->kp_q = cfg->alpha_c * cfg->L_q;
    foc->ki = cfg->alpha_c * cfg->R_s;
    foc->ks_p = 2.0f * cfg->alpha_s * cfg->J;
    foc->ks_i = cfg->alpha_s * cfg->alpha_s * cfg->J;
    foc->k_t = 1.5f * (float)cfg->n_p * cfg->psi_f;
    foc->tau_max = foc->k_t * cfg->i_max;
    foc->ko_p = 8.0f * cfg->alpha_s;      /* the tracking loop at 4 alpha_s, critically damped */
    foc->ko_i = 16.0f * cfg->alpha_s * cfg->alpha_s;
    foc->scale_full = (float)(1L << (dev->width - 2)); /* codes per Vdc: FULL */
    foc->w_hat = w_m0;

    mdfqm_set_period(dev, cfg->period);
    mdfqm_set_osr(dev, cfg->osr);
    mdfqm_set_dead_time(dev, cfg->dead);
    mdfqm_set_min_pulse(dev, cfg->min_pulse);
    mdfqm_set_adc_offset(dev, cfg->adc_offset);
    mdfqm_set_zero_policy(dev, cfg->fewest_transitions != 0);
    mdfqm_set_modulation(dev, cfg->mode, cfg->bits);
    mdfqm_set_fault_reaction(dev, MDFQM_SOURCE_FAULT, (mdfqm_reaction_t)cfg->fault_reaction);
    mdfqm_irq_enable(dev, MDFQM_TOP__IRQ_ENABLE__SAMPLE_bm | MDFQM_TOP__IRQ_ENABLE__FAULT_bm
                              | MDFQM_TOP__IRQ_ENABLE__WATCHDOG_bm);
    mdfqm_enable(dev, true);
    return 0;
}

void mdfqm_foc_irq(mdfqm_foc_t *foc) {
    mdfqm_irq_causes_t causes = mdfqm_irq_handle(&foc->dev);
    if (causes.sample) {
        if (foc->period_started)
            foc->missed++;  /* no conversion came in the last period: its reference is stale */
        foc->period_started = true;
        foc->periods++;
    }
    if (causes.fault) {
        foc->faults++;
        foc->faulted = true;
    }
    if (causes.watchdog)
        foc->watchdogs++;
}

/* The encoder tracking loop: the speed estimate after this count; the angle kept relative to
 * the last count, so that float precision does not degrade as the count grows. */
static float track_speed(mdfqm_foc_t *foc, int32_t count) {
    if (!foc->tracking) {
        foc->tracking = true;
        foc->count_base = count;
        foc->theta_hat_rel = 0.0f;
    }
    float theta_rel = TWO_PI * (float)(count - foc->count_base) / (float)foc->cfg.encoder_counts;
    float err = theta_rel - foc->theta_hat_rel;
    foc->theta_hat_rel += foc->T_c * (foc->w_hat + foc->ko_p * err);
    foc->w_hat += foc->T_c * foc->ko_i * err;
    foc->theta_hat_rel -= theta_rel;
    foc->count_base = count;
    return foc->w_hat;
}

/* The currents (A) of the sample(s) the control law uses, into i_alpha / i_beta. */
static void measure_currents(mdfqm_foc_t *foc) {
    const mdfqm_foc_config_t *c = &foc->cfg;
    unsigned n = c->average ? foc->ring_fill : 1u;
    unsigned newest = (foc->ring_next + MDFQM_FOC_MAX_OSR - 1u) % MDFQM_FOC_MAX_OSR;
    int32_t sum[3] = {0, 0, 0};
    for (unsigned k = 0; k < n; k++) {
        const int32_t *s = foc->ring[(newest + MDFQM_FOC_MAX_OSR - k) % MDFQM_FOC_MAX_OSR];
        for (unsigned i = 0; i < 3; i++)
            sum[i] += s[i];
    }
    float scale = c->adc_lsb / (float)n;
    float i_a = scale * (float)sum[0], i_b = scale * (float)sum[1], i_c = scale * (float)sum[2];
    foc->i_alpha = (2.0f / 3.0f) * (i_a - 0.5f * (i_b + i_c));
    foc->i_beta = (i_b - i_c) / SQRT3;
}

static void control_step(mdfqm_foc_t *foc, int32_t count, float u_dc, float w_ref) {
    const mdfqm_foc_config_t *c = &foc->cfg;
    float w_m = track_speed(foc, count);
    float w_e = (float)c->n_p * w_m;
    /* the electrical angle of the count, reduced in integers before it becomes a float */
    int32_t counts = (int32_t)c->encoder_counts;
    int32_t pos = count % counts;
    if (pos < 0)
        pos += counts;
    int32_t elec = (int32_t)(((int64_t)pos * c->n_p) % counts);
    float theta_e = TWO_PI * (float)elec / (float)counts;

    /* speed I-P with clamping anti-windup */
    float e_w = w_ref - w_m;
    float tau_free = foc->int_s + foc->ks_i * foc->T_c * e_w - foc->ks_p * w_m;
    float tau = tau_free > foc->tau_max ? foc->tau_max
                : tau_free < -foc->tau_max ? -foc->tau_max : tau_free;
    if (tau == tau_free)
        foc->int_s += foc->ks_i * foc->T_c * e_w;
    foc->i_q_ref = tau / foc->k_t;

    /* dq currents */
    float cs = cosf(theta_e), sn = sinf(theta_e);
    float i_d = foc->i_alpha * cs + foc->i_beta * sn;
    float i_q = -foc->i_alpha * sn + foc->i_beta * cs;
    foc->i_d_meas = i_d;
    foc->i_q_meas = i_q;
    float e_d = -i_d, e_q = foc->i_q_ref - i_q;
    float u_d = foc->kp_d * e_d + foc->int_d;
    float u_q = foc->kp_q * e_q + foc->int_q;
    if (c->decoupling) {
        u_d -= w_e * c->L_q * i_q;
        u_q += w_e * (c->L_d * i_d + c->psi_f);
    }
    /* the voltage limited to the linear range, back-calculation anti-windup */
    float mag = sqrtf(u_d * u_d + u_q * u_q), u_max = LINEAR_RANGE * u_dc;
    float k = mag > u_max ? u_max / mag : 1.0f;
    float ul_d = k * u_d, ul_q = k * u_q;
    foc->int_d += foc->ki * foc->T_c * (e_d + (ul_d - u_d) / foc->kp_d);
    foc->int_q += foc->ki * foc->T_c * (e_q + (ul_q - u_q) / foc->kp_q);

    /* inverse Park at the angle advanced by the computation delay and the hold */
    float angle = theta_e + (c->delay_compensation ? 1.5f * w_e * foc->T_c : 0.0f);
    float ca = cosf(angle), sa = sinf(angle);
    float u_alpha = ul_d * ca - ul_q * sa, u_beta = ul_d * sa + ul_q * ca;
    float scale = foc->scale_full / u_dc;
    foc->codes[0] = (int32_t)lrintf(scale * u_alpha);
    foc->codes[1] = (int32_t)lrintf(scale * (-0.5f * u_alpha + 0.5f * SQRT3 * u_beta));
    foc->codes[2] = (int32_t)lrintf(scale * (-0.5f * u_alpha - 0.5f * SQRT3 * u_beta));
    mdfqm_write_reference(&foc->dev, foc->codes);
    foc->steps++;
}

bool mdfqm_foc_adc(mdfqm_foc_t *foc, const int32_t adc[3], int32_t encoder_count, float u_dc,
                   float w_ref) {
    for (unsigned i = 0; i < 3; i++)
        foc->ring[foc->ring_next][i] = adc[i];
    foc->ring_next = (foc->ring_next + 1u) % MDFQM_FOC_MAX_OSR;
    if (foc->ring_fill < foc->cfg.osr)
        foc->ring_fill++;
    if (!foc->period_started)
        return false;
    foc->period_started = false;
    if (foc->faulted) {
        float w = track_speed(foc, encoder_count);
        if (!foc->all_off_sent && fabsf(w) < foc->cfg.asc_exit_speed) {
            mdfqm_fault_all_off(&foc->dev);
            foc->all_off_sent = true;
        }
        return false;
    }
    measure_currents(foc);
    control_step(foc, encoder_count, u_dc, w_ref);
    return true;
}
