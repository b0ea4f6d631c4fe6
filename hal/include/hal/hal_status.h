/*
 * Status codes returned by HAL functions that can fail.
 *
 * HAL_OK is 0. Interrupt context: yes (constants only).
 */
#ifndef HAL_STATUS_H
#define HAL_STATUS_H

typedef enum {
    HAL_OK = 0,
    HAL_ERR_PARAM, /* an argument is outside its documented range */
    HAL_ERR_BUSY,  /* a queue is full: retry later (never blocks) */
    HAL_ERR_EMPTY, /* nothing to receive */
    HAL_ERR_HW     /* the peripheral reports an error (bus-off, ...) */
} hal_status_t;

#endif /* HAL_STATUS_H */
