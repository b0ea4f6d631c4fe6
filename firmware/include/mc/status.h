/*
 * Status codes shared by every firmware module.
 *
 * A function that can fail returns mc_status_t; MC_OK is 0 so that
 * `if (status != MC_OK)` reads naturally. Non-finite inputs are always an
 * error (MC_ERR_NONFINITE), never silently mapped to zero.
 * Interrupt context: yes (constants only).
 */
#ifndef MC_STATUS_H
#define MC_STATUS_H

typedef enum {
    MC_OK = 0,
    MC_ERR_NONFINITE, /* an input or result is NaN or +-Inf */
    MC_ERR_RANGE,     /* an input is outside its documented range */
    MC_ERR_PARAM,     /* an init/config parameter is invalid */
    MC_ERR_STATE      /* call not allowed in the current state */
} mc_status_t;

#endif /* MC_STATUS_H */
