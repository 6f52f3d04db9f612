/* rs_track replay files: record/replay round trip, raw dumps, damage, missing files. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <dirent.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>
#include <cmocka.h>
#include <math.h>

#include "raystream/rs_track.h"

static char path[256];

/* Temporary files the recorder may have left next to `path`. */
static int count_tmp_files(void)
{
	char prefix[300];
	snprintf(prefix, sizeof prefix, "%s.tmp-", path);
	DIR *d = opendir(".");
	assert_non_null(d);
	int n = 0;
	for (struct dirent *e; (e = readdir(d)) != NULL;)
		n += strncmp(e->d_name, prefix, strlen(prefix)) == 0;
	closedir(d);
	return n;
}

static int setup(void **state)
{
	snprintf(path, sizeof path, "test_track_replay_%d.rec", (int)getpid());
	return 0;
}

static int teardown(void **state)
{
	remove(path);
	return 0;
}

/* Record n sim samples (noise on, so positions are not trivially regular). */
static void record(int n, struct rs_marker_sample *ref)
{
	struct rs_sim_desc d = {.seed = 11, .noise_sigma_m = 0.0005, .dropout_prob = 0.05};
	struct rs_sim *sim = NULL;
	struct rs_track_recorder *rec = NULL;
	assert_int_equal(rs_sim_create(&d, &sim, NULL), RS_OK);
	assert_int_equal(rs_track_recorder_create(path, &rec, NULL), RS_OK);
	for (int i = 0; i < n; i++) {
		assert_int_equal(rs_sim_next(sim, &ref[i], NULL, NULL), RS_OK);
		ref[i].host_time_s = 1000.0 + i * 0.01;
		assert_int_equal(rs_track_recorder_write(rec, &ref[i], NULL), RS_OK);
	}
	assert_int_equal(rs_track_recorder_destroy(&rec, NULL), RS_OK);
	assert_null(rec);
	rs_sim_destroy(&sim);
}

static void round_trip_preserves_samples(void **state)
{
	static struct rs_marker_sample ref[500];
	record(500, ref);
	struct rs_track_source *src = NULL;
	assert_int_equal(rs_track_replay_open(path, NULL, &src, NULL), RS_OK);
	struct rs_marker_sample s;
	for (int i = 0; i < 500; i++) {
		assert_int_equal(rs_track_source_read(src, &s, 0, NULL), RS_OK);
		assert_int_equal(s.sequence, ref[i].sequence);
		assert_true(s.device_time_us == ref[i].device_time_us);
		assert_true(s.host_time_s == ref[i].host_time_s); /* stored bit-exact */
		for (int m = 0; m < 3; m++) {
			assert_int_equal(s.markers[m].flags, ref[i].markers[m].flags);
			for (int a = 0; a < 3; a++) /* micrometre quantisation: 0.5 um */
				assert_true(fabs(s.markers[m].position[a] -
				                 ref[i].markers[m].position[a]) <= 0.5e-6 + 1e-12);
		}
	}
	assert_int_equal(rs_track_source_read(src, &s, 0, NULL), RS_END);
	/* Reopen rewinds. */
	assert_int_equal(rs_track_source_reopen(src, NULL), RS_OK);
	assert_int_equal(rs_track_source_read(src, &s, 0, NULL), RS_OK);
	assert_int_equal(s.sequence, ref[0].sequence);
	rs_track_source_destroy(&src);
}

static void raw_frame_dump_replays(void **state)
{
	FILE *f = fopen(path, "wb");
	assert_non_null(f);
	for (uint32_t i = 0; i < 20; i++) {
		struct rs_marker_sample s = {
		    .sequence = i, .device_time_us = 500000 + i * 1000, .marker_count = 3};
		uint8_t frame[RS_PROTO_FRAME_SIZE];
		assert_int_equal(rs_proto_encode(&s, frame, NULL), RS_OK);
		assert_int_equal(fwrite(frame, 1, sizeof frame, f), sizeof frame);
	}
	fclose(f);
	struct rs_track_source *src = NULL;
	assert_int_equal(rs_track_replay_open(path, NULL, &src, NULL), RS_OK);
	struct rs_marker_sample s;
	for (uint32_t i = 0; i < 20; i++) {
		assert_int_equal(rs_track_source_read(src, &s, 0, NULL), RS_OK);
		assert_int_equal(s.sequence, i);
		assert_true(fabs(s.host_time_s - (0.5 + i * 0.001)) < 1e-9); /* = device time */
	}
	assert_int_equal(rs_track_source_read(src, &s, 0, NULL), RS_END);
	rs_track_source_destroy(&src);
}

static void damaged_record_is_counted_and_skipped(void **state)
{
	static struct rs_marker_sample ref[10];
	record(10, ref);
	FILE *f = fopen(path, "r+b");
	assert_non_null(f);
	/* Record 3's frame starts at 16 + 3 * 70 + 8; flip a payload byte. */
	assert_int_equal(fseek(f, 16 + 3 * 70 + 8 + 30, SEEK_SET), 0);
	fputc(0xFF ^ 0x5C, f);
	fclose(f);
	struct rs_track_source *src = NULL;
	assert_int_equal(rs_track_replay_open(path, NULL, &src, NULL), RS_OK);
	struct rs_marker_sample s;
	int n = 0;
	while (rs_track_source_read(src, &s, 0, NULL) == RS_OK) {
		assert_true(s.sequence != ref[3].sequence);
		n++;
	}
	assert_int_equal(n, 9);
	struct rs_track_source_stats st;
	rs_track_source_get_stats(src, &st);
	assert_int_equal(st.proto.crc_errors, 1);
	assert_int_equal(st.proto.lost_frames, 1);
	rs_track_source_destroy(&src);
}

static void truncated_file_ends_cleanly(void **state)
{
	static struct rs_marker_sample ref[10];
	record(10, ref);
	assert_int_equal(truncate(path, 16 + 5 * 70 + 30), 0);
	struct rs_track_source *src = NULL;
	assert_int_equal(rs_track_replay_open(path, NULL, &src, NULL), RS_OK);
	struct rs_marker_sample s;
	int n = 0;
	enum rs_status st;
	while ((st = rs_track_source_read(src, &s, 0, NULL)) == RS_OK)
		n++;
	assert_int_equal(st, RS_END);
	assert_int_equal(n, 5);
	rs_track_source_destroy(&src);
}

static void missing_file_is_not_found(void **state)
{
	struct rs_track_source *src = NULL;
	struct rs_error err;
	assert_int_equal(rs_track_replay_open("/nonexistent/raystream.rec", NULL, &src, &err),
	                 RS_ERR_NOT_FOUND);
	assert_null(src);
	assert_non_null(strstr(err.message, "raystream.rec"));
}

/* Without the header any file would read as an empty raw dump: a regular file with no
 * frame is refused at open (replay:data/cow.obj used to "replay" 0 samples, exit 0). */
static void non_recording_is_refused(void **state)
{
	const char *bodies[] = {"", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"};
	for (size_t i = 0; i < 2; i++) {
		FILE *f = fopen(path, "wb");
		assert_non_null(f);
		fputs(bodies[i], f);
		fclose(f);
		struct rs_track_source *src = NULL;
		struct rs_error err;
		assert_int_equal(rs_track_replay_open(path, NULL, &src, &err), RS_ERR_BAD_DATA);
		assert_null(src);
		assert_non_null(strstr(err.message, "not a recording"));
	}
}

static void unknown_recording_version_is_unsupported(void **state)
{
	FILE *f = fopen(path, "wb");
	assert_non_null(f);
	fwrite("RSTRKREC\x02\0\0\0\x3e\0\0\0", 1, 16, f);
	fclose(f);
	struct rs_track_source *src = NULL;
	struct rs_error err;
	assert_int_equal(rs_track_replay_open(path, NULL, &src, &err), RS_ERR_UNSUPPORTED);
	assert_null(src);
}

static void unencodable_sample_is_not_recorded(void **state)
{
	struct rs_track_recorder *rec = NULL;
	assert_int_equal(rs_track_recorder_create(path, &rec, NULL), RS_OK);
	struct rs_marker_sample s = {.marker_count = 3};
	s.markers[0].position[0] = NAN;
	s.markers[0].flags = RS_MARKER_VALID;
	struct rs_error err;
	assert_int_equal(rs_track_recorder_write(rec, &s, &err), RS_ERR_BAD_DATA);
	assert_int_equal(rs_track_recorder_destroy(&rec, NULL), RS_OK);
	struct rs_track_source *src = NULL;
	assert_int_equal(rs_track_replay_open(path, NULL, &src, NULL), RS_OK);
	assert_int_equal(rs_track_source_read(src, &s, 0, NULL), RS_END);
	rs_track_source_destroy(&src);
}

static void recorder_reports_unwritable_path(void **state)
{
	struct rs_track_recorder *rec = NULL;
	struct rs_error err;
	assert_int_equal(rs_track_recorder_create("/nonexistent/dir/x.rec", &rec, &err), RS_ERR_IO);
	assert_null(rec);
}

/* The recording appears under its name only once it is complete: an existing file is
 * untouched while recording, and the recorder leaves no stray temporary file. */
static void recording_appears_only_when_finished(void **state)
{
	FILE *f = fopen(path, "wb");
	assert_non_null(f);
	fputs("old", f);
	fclose(f);
	struct rs_track_recorder *rec = NULL;
	assert_int_equal(rs_track_recorder_create(path, &rec, NULL), RS_OK);
	struct rs_marker_sample s = {.sequence = 1, .marker_count = 3};
	for (int i = 0; i < 100; i++) {
		s.sequence = (uint32_t)i;
		assert_int_equal(rs_track_recorder_write(rec, &s, NULL), RS_OK);
	}
	struct stat sb;
	assert_int_equal(stat(path, &sb), 0);
	assert_int_equal(sb.st_size, 3); /* still the old file */
	assert_int_equal(rs_track_recorder_destroy(&rec, NULL), RS_OK);
	assert_int_equal(stat(path, &sb), 0);
	assert_int_equal(sb.st_size, 16 + 100 * 70);
	assert_int_equal(count_tmp_files(), 0);
}

/* A write that fails (here: the file size limit) must not leave a partial recording. */
static void failed_recording_leaves_no_file(void **state)
{
	struct rlimit old, small;
	assert_int_equal(getrlimit(RLIMIT_FSIZE, &old), 0);
	void (*old_handler)(int) = signal(SIGXFSZ, SIG_IGN);
	small = old;
	small.rlim_cur = 4096;
	assert_int_equal(setrlimit(RLIMIT_FSIZE, &small), 0);
	struct rs_track_recorder *rec = NULL;
	assert_int_equal(rs_track_recorder_create(path, &rec, NULL), RS_OK);
	struct rs_marker_sample s = {.marker_count = 3};
	enum rs_status st = RS_OK;
	for (int i = 0; i < 1000 && st == RS_OK; i++) { /* 70 kB: far past the limit */
		s.sequence = (uint32_t)i;
		st = rs_track_recorder_write(rec, &s, NULL);
	}
	struct rs_error err;
	enum rs_status fin = rs_track_recorder_destroy(&rec, &err);
	setrlimit(RLIMIT_FSIZE, &old);
	signal(SIGXFSZ, old_handler);
	assert_true(st == RS_ERR_IO || fin == RS_ERR_IO);
	assert_int_equal(fin, RS_ERR_IO);
	assert_null(rec);
	assert_int_equal(access(path, F_OK), -1);
	assert_int_equal(count_tmp_files(), 0);
}

static void recorder_rejects_directory(void **state)
{
	struct rs_track_recorder *rec = NULL;
	struct rs_error err;
	assert_int_equal(rs_track_recorder_create(".", &rec, &err), RS_ERR_IO);
	assert_null(rec);
	assert_non_null(strstr(err.message, "directory"));
}

/* A target that exists but is not a regular file is refused and left as it was: renaming
 * the finished recording over a FIFO or symlink (or, as root, a device node such as
 * /dev/null) would replace the node itself with a regular file. */
static void recorder_refuses_non_regular_targets(void **state)
{
	char fifo[300], link[300];
	snprintf(fifo, sizeof fifo, "%s.fifo", path);
	snprintf(link, sizeof link, "%s.link", path);
	remove(fifo);
	remove(link);
	assert_int_equal(mkfifo(fifo, 0600), 0);
	FILE *f = fopen(path, "wb");
	assert_non_null(f);
	fclose(f);
	assert_int_equal(symlink(path, link), 0);
	const char *targets[] = {fifo, link};
	for (int i = 0; i < 2; i++) {
		struct rs_track_recorder *rec = NULL;
		struct rs_error err;
		assert_int_equal(rs_track_recorder_create(targets[i], &rec, &err), RS_ERR_IO);
		assert_null(rec);
		assert_non_null(strstr(err.message, "not a regular file"));
	}
	struct stat sb;
	assert_int_equal(lstat(fifo, &sb), 0);
	assert_true(S_ISFIFO(sb.st_mode));
	assert_int_equal(lstat(link, &sb), 0);
	assert_true(S_ISLNK(sb.st_mode));
	remove(fifo);
	remove(link);
}

/* A record whose host time is NaN, infinite or absurd (a damaged or hand-made file) is
 * replayed with its device time instead, so no non-finite time reaches the caller. */
static void bad_recorded_time_falls_back_to_device_time(void **state)
{
	struct rs_track_recorder *rec = NULL;
	assert_int_equal(rs_track_recorder_create(path, &rec, NULL), RS_OK);
	const double times[] = {NAN, INFINITY, -1e300, 12.5};
	for (uint32_t i = 0; i < 4; i++) {
		struct rs_marker_sample s = {
		    .sequence = i, .device_time_us = 2000000 + i, .marker_count = 3};
		s.host_time_s = times[i];
		assert_int_equal(rs_track_recorder_write(rec, &s, NULL), RS_OK);
	}
	assert_int_equal(rs_track_recorder_destroy(&rec, NULL), RS_OK);
	for (int realtime = 0; realtime < 2; realtime++) {
		struct rs_track_replay_desc d = {.realtime = realtime};
		struct rs_track_source *src = NULL;
		assert_int_equal(rs_track_replay_open(path, &d, &src, NULL), RS_OK);
		struct rs_marker_sample s;
		for (uint32_t i = 0; i < 4; i++) {
			assert_int_equal(rs_track_source_read(src, &s, -1, NULL), RS_OK);
			double want = i < 3 ? 2.0 + i * 1e-6 : 12.5;
			assert_true(fabs(s.host_time_s - want) < 1e-9);
		}
		rs_track_source_destroy(&src);
	}
}

/* An endless input without frames must not trap a read: it comes back as RS_TIMEOUT
 * (after at most 1 MiB) so the caller keeps its timeouts and signals. */
static void endless_frameless_input_times_out(void **state)
{
	struct rs_track_source *src = NULL;
	assert_int_equal(rs_track_replay_open("/dev/zero", NULL, &src, NULL), RS_OK);
	struct rs_marker_sample s;
	for (int i = 0; i < 3; i++)
		assert_int_equal(rs_track_source_read(src, &s, 0, NULL), RS_TIMEOUT);
	struct rs_track_source_stats st;
	rs_track_source_get_stats(src, &st);
	assert_true(st.proto.garbage_bytes >= 3u << 20);
	rs_track_source_destroy(&src);
}

static void realtime_replay_keeps_recorded_spacing(void **state)
{
	/* 11 records 10 ms apart replay in >= 95 ms of host time. */
	static struct rs_marker_sample ref[11];
	record(11, ref);
	struct rs_track_replay_desc d = {.realtime = 1};
	struct rs_track_source *src = NULL;
	assert_int_equal(rs_track_replay_open(path, &d, &src, NULL), RS_OK);
	struct rs_marker_sample s;
	double t0 = rs_track_now_s();
	for (int i = 0; i < 11; i++)
		while (rs_track_source_read(src, &s, 2, NULL) == RS_TIMEOUT) {
		}
	assert_true(rs_track_now_s() - t0 >= 0.095);
	rs_track_source_destroy(&src);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
	    cmocka_unit_test_setup_teardown(round_trip_preserves_samples, setup, teardown),
	    cmocka_unit_test_setup_teardown(raw_frame_dump_replays, setup, teardown),
	    cmocka_unit_test_setup_teardown(damaged_record_is_counted_and_skipped, setup, teardown),
	    cmocka_unit_test_setup_teardown(truncated_file_ends_cleanly, setup, teardown),
	    cmocka_unit_test_setup_teardown(missing_file_is_not_found, setup, teardown),
	    cmocka_unit_test_setup_teardown(non_recording_is_refused, setup, teardown),
	    cmocka_unit_test_setup_teardown(unknown_recording_version_is_unsupported, setup,
	                                    teardown),
	    cmocka_unit_test_setup_teardown(unencodable_sample_is_not_recorded, setup, teardown),
	    cmocka_unit_test_setup_teardown(recorder_reports_unwritable_path, setup, teardown),
	    cmocka_unit_test_setup_teardown(recording_appears_only_when_finished, setup, teardown),
	    cmocka_unit_test_setup_teardown(failed_recording_leaves_no_file, setup, teardown),
	    cmocka_unit_test_setup_teardown(recorder_refuses_non_regular_targets, setup, teardown),
	    cmocka_unit_test_setup_teardown(recorder_rejects_directory, setup, teardown),
	    cmocka_unit_test_setup_teardown(bad_recorded_time_falls_back_to_device_time, setup,
	                                    teardown),
	    cmocka_unit_test_setup_teardown(endless_frameless_input_times_out, setup, teardown),
	    cmocka_unit_test_setup_teardown(realtime_replay_keeps_recorded_spacing, setup,
	                                    teardown),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
