/*
 * raystream-track --pty: play any source (typically sim:...&realtime=1) as protocol frames
 * into a new pseudo-terminal, so another process can open it as serial:PATH. The slave
 * path is printed first, on a line of its own.
 */
#include <stdio.h>

#include "raystream/rs_track.h"
#include "raystream/rs_serial.h"
#include "track_tool.h"

int track_serve_pty(struct rs_track_source *src, long long count, double duration_s,
                    volatile sig_atomic_t *stop)
{
	struct rs_error err;
	struct rs_serial_pty *pty = NULL;
	if (rs_serial_pty_create(&pty, &err) != RS_OK) {
		fprintf(stderr, "raystream-track: %s\n", err.message);
		return 1;
	}
	printf("%s\n", rs_serial_pty_path(pty));
	fflush(stdout);
	int code = 0;
	long long n = 0;
	double start = rs_track_now_s();
	while (!*stop && (!count || n < count) &&
	       !(duration_s > 0 && rs_track_now_s() - start >= duration_s)) {
		struct rs_marker_sample s;
		enum rs_status st = rs_track_source_read(src, &s, 100, NULL);
		if (st == RS_TIMEOUT)
			continue;
		if (st == RS_END)
			break;
		uint8_t frame[RS_PROTO_FRAME_SIZE];
		if (st != RS_OK || rs_proto_encode(&s, frame, &err) != RS_OK) {
			fprintf(stderr, "raystream-track: %s\n",
			        st != RS_OK ? rs_track_source_last_error(src) : err.message);
			code = 1;
			break;
		}
		/* While nobody reads the slave the line fills up: wait in short steps so a
		 * signal or the duration still ends the run, and keep each frame whole. */
		size_t done = 0;
		enum rs_status ws = RS_TIMEOUT;
		while (ws == RS_TIMEOUT && !*stop &&
		       !(duration_s > 0 && rs_track_now_s() - start >= duration_s)) {
			size_t k = 0;
			ws = rs_serial_pty_write_timeout(pty, frame + done, sizeof frame - done,
			                                 100, &k, &err);
			done += k;
		}
		if (ws != RS_OK && ws != RS_TIMEOUT) {
			fprintf(stderr, "raystream-track: %s\n", err.message);
			code = 1;
			break;
		}
		if (ws == RS_OK)
			n++;
	}
	rs_serial_pty_destroy(&pty);
	return code;
}
