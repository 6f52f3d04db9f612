/* Write-then-rename helpers shared by the image writers. */
#ifndef RS_ATOMIC_FILE_H
#define RS_ATOMIC_FILE_H

#include <stdio.h>

#include "raystream/rs_status.h"

/* Open a temporary file beside `path`; its name is written to tmp_path (tmp_size bytes). */
enum rs_status rs_atomic_open(const char *path, char *tmp_path, size_t tmp_size, FILE **out,
                              struct rs_error *err);
/* Close; on success rename onto path, otherwise remove the temporary. */
enum rs_status rs_atomic_commit(FILE *file, const char *tmp_path, const char *path, int ok,
                                struct rs_error *err);

#endif
