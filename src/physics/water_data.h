/* water_data.h - the optical-constant CSV files compiled into the library. */
#ifndef SEA_WATER_DATA_H
#define SEA_WATER_DATA_H

#include "internal.h"

typedef struct {
    const char *name; /* file name without .csv, e.g. "water_nk_hale_querry" */
    const char *text; /* the file's exact text */
} sea_data_file;

/* Terminated by an entry whose name is NULL. */
SEA_INTERNAL extern const sea_data_file sea_data_files[];

#endif
