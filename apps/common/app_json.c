/* Small JSON files for the apps (--stats, --port-file): printed with cJSON and written
 * through a temporary file and a rename, so a reader never sees half a file. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app_net.h"

enum rs_status app_write_json(const char *path, const cJSON *doc, struct rs_error *err)
{
	char *text = cJSON_Print(doc);
	if (!text)
		return rs_error_set(err, RS_ERR_NO_MEMORY, "out of memory formatting %s", path);
	size_t n = strlen(path) + 16;
	char *tmp = malloc(n);
	FILE *f = NULL;
	if (tmp) {
		snprintf(tmp, n, "%s.tmp", path);
		f = fopen(tmp, "wb");
	}
	int ok = f && fputs(text, f) >= 0 && fputc('\n', f) != EOF;
	ok = f && fclose(f) == 0 && ok;
	cJSON_free(text);
	if (ok && rename(tmp, path) == 0) {
		free(tmp);
		return RS_OK;
	}
	if (tmp)
		remove(tmp);
	free(tmp);
	return rs_error_set(err, RS_ERR_IO, "cannot write %s", path);
}
