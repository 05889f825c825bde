/* status.c - error records and library start-up. */
#include "config.h"

#include <stdarg.h>
#include <stdio.h>

#include <gsl/gsl_errno.h>

#include "seabake.h"

sea_status sea_fail(sea_error *err, sea_status status, const char *fmt, ...)
{
    if (err != NULL) {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(err->msg, sizeof err->msg, fmt, ap);
        va_end(ap);
    }
    return status;
}

const char *sea_status_name(sea_status status)
{
    switch (status) {
    case SEA_OK: return "ok";
    case SEA_ERR_DOMAIN: return "value out of range";
    case SEA_ERR_PARSE: return "malformed input";
    case SEA_ERR_IO: return "input/output error";
    case SEA_ERR_NOMEM: return "out of memory";
    case SEA_ERR_NUMERIC: return "numerical failure";
    case SEA_ERR_CANCELLED: return "cancelled";
    }
    return "unknown status";
}

void sea_init(void)
{
    /* GSL's default handler aborts the process; every GSL status is checked. */
    gsl_set_error_handler_off();
}
