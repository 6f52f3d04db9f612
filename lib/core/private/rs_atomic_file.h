/*
 * Private to raystream (never installed; in-tree modules and tools only): the one
 * write-to-a-temporary-then-rename mechanism. A failed or interrupted write never leaves a
 * half-written file under the real name, and a target that exists but is not a regular
 * file (a device, a FIFO: rename() as root would replace the node) is refused and kept.
 *
 *   struct rs_atomic_file af;
 *   if (rs_atomic_open(&af, path, err) != RS_OK) return ...;
 *   ... fwrite(..., af.f) ...
 *   return rs_atomic_commit(&af, ok, err);       (renames, or removes the temporary)
 *
 * Several files that must appear together: rs_atomic_finish() each (flush, fsync, close),
 * then rs_atomic_commit() each once all have finished.
 */
#ifndef RS_ATOMIC_FILE_H
#define RS_ATOMIC_FILE_H

#include <stdbool.h>
#include <stdio.h>

#include "raystream/rs_status.h"

struct rs_atomic_file {
	FILE *f;    /* the temporary, open for binary writing; NULL once finished */
	char *path; /* the final name (a copy) */
	char *tmp;  /* the temporary's name; NULL once committed or removed */
};

/* Create a temporary beside `path` (mode 0644). On failure `af` holds nothing to release. */
enum rs_status rs_atomic_open(struct rs_atomic_file *af, const char *path, struct rs_error *err);

/* Flush, fsync and close the temporary; when !ok or that fails it is removed. */
enum rs_status rs_atomic_finish(struct rs_atomic_file *af, bool ok, struct rs_error *err);

/*
 * Finish (if not yet), then rename the temporary onto the final name when ok, else remove
 * it; releases `af` either way. With !ok the status already in `err` (or RS_ERR_IO) is
 * returned. A zeroed or already committed `af` is allowed (RS_OK).
 */
enum rs_status rs_atomic_commit(struct rs_atomic_file *af, bool ok, struct rs_error *err);

#endif
