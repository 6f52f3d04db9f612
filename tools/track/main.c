/*
 * raystream-track: open a tracker source from a URI, solve poses (rs_pose), optionally
 * filter/predict, print them with live fault counters, record to a replay file.
 * Errors are one line on stderr and a non-zero exit (1 runtime, 2 usage).
 */
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "raystream/rs_cli.h"
#ifdef RS_HAVE_OPTICAL
#include "raystream/rs_optical.h"
#endif
#include "raystream/rs_pose.h"
#include "raystream/rs_track.h"
#include "raystream/rs_tracker.h"
#include "tool_common.h"
#include "track_tool.h"

#define TOOL "raystream-track"

static volatile sig_atomic_t stop_requested;

static void on_signal(int sig)
{
	(void)sig;
	stop_requested = 1;
}

struct options {
	const char *uri, *record, *layout;
	long long count;
	double duration_s, predict_ms, sigma_mm, stats_every_s, timeout_s;
	int filter, quiet, reconnect, bench, bench_samples, pty;
};

static enum rs_status parse_count(void *out, const char *v, struct rs_error *err)
{
	char *end = NULL;
	errno = 0;
	double d = strtod(v, &end);
	/* 1e18 keeps the conversion to long long defined. */
	if (!v[0] || *end || errno || !(d >= 1 && d <= 1e18) || d != floor(d))
		return rs_error_set(err, RS_ERR_INVALID, "'%s' is not a whole number 1..1e18", v);
	*(long long *)out = (long long)d;
	return RS_OK;
}

static const char about[] =
    "URI: hid:VID:PID[:SERIAL]  usb:VID:PID  serial:/dev/PATH[?baud=N]\n"
    "     sim:[seed=N&noise=0.5mm&rate=120&script=walk,turn&realtime=1&...]\n"
    "          (not real-time: one pass of the script, 6 s of motion by default,\n"
    "          unless duration=S, --count or --duration say otherwise)\n"
    "     replay:FILE[?realtime=1]\n"
    "     video:LEFT,RIGHT?calib=RIG[&rate=60]  (image sequences or videos)\n"
    "     cam:0,1?calib=RIG   (two V4L2 cameras; see docs/optical.md)\n"
    "Optical samples also print stated=DEG/MM (the pose's expected error; clean poses\n"
    "are ~1x it off) and bound=DEG/MM (the integrity bound: the most one undetected\n"
    "stray spot could put it off and still pass every test); with a layout verifier\n"
    "(\"verifier\": [x,y,z] in the layout=FILE of the source) verifier=N, the views it\n"
    "was seen in where the pose puts it (0: hidden; a stray it refuses: optical=\n"
    "RS_OPTICAL_VERIFIER).\n"
    "One-letter spellings: -n --count, -d --duration, -r --record, -l --layout,\n"
    "-f --filter, -p --predict, -q --quiet; --bench N is --bench-samples N.\n";

static int parse_args(int argc, char **argv, struct options *o)
{
	*o = (struct options){
	    .sigma_mm = 0.5, .stats_every_s = 1.0, .timeout_s = 5.0, .bench_samples = 2000};
	bool filter = false, quiet = false, reconnect = false, bench = false, pty = false;
	uint32_t samples = 2000;
	const struct rs_cli_option opts[] = {
	    RS_CLI_CALL_OPT("--count", &o->count, parse_count, "N", "stop after N samples"),
	    RS_CLI_DOUBLE_OPT("--duration", &o->duration_s, "S", 1e-6, 1e9, "stop after S seconds"),
	    RS_CLI_STRING_OPT("--record", &o->record, "FILE",
	                      "record every sample (replay with replay:FILE)"),
	    {.name = "--layout",
	     .kind = RS_CLI_STRING,
	     .out = &o->layout,
	     .arg = "FILE",
	     .help = "marker layout JSON",
	     .fallback = "10 x 8 cm triangle"},
	    RS_CLI_FLAG_OPT("--filter", &filter, "1-euro filter the poses"),
	    RS_CLI_DOUBLE_OPT("--predict", &o->predict_ms, "0..30", 0,
	                      RS_POSE_MAX_PREDICTION_S * 1e3,
	                      "predict MS ms ahead of each sample (implies --filter)"),
	    RS_CLI_DOUBLE_OPT("--sigma", &o->sigma_mm, "MM", 1e-6, 1e3,
	                      "expected marker noise for the solver, mm"),
	    RS_CLI_DOUBLE_OPT("--stats", &o->stats_every_s, "S", 0, 1e9,
	                      "fault counters every S seconds (0: only at the end)"),
	    RS_CLI_DOUBLE_OPT("--timeout", &o->timeout_s, "S", 1e-6, 1e9,
	                      "give up after S seconds without a sample"),
	    RS_CLI_FLAG_OPT("--reconnect", &reconnect,
	                    "reopen a disconnected device instead of exiting"),
	    RS_CLI_FLAG_OPT("--quiet", &quiet, "no pose lines"),
	    RS_CLI_FLAG_OPT("--pty", &pty,
	                    "play the source into a new pseudo-terminal (path printed) for "
	                    "serial:PATH elsewhere"),
	    RS_CLI_FLAG_OPT("--bench", &bench, "protocol throughput and pty latency benchmark"),
	    RS_CLI_U32_OPT("--bench-samples", &samples, 10, 10000000, "--bench: samples"),
	};
	static const char *const short_names[][2] = {
	    {"-n", "--count"},  {"-d", "--duration"}, {"-r", "--record"}, {"-l", "--layout"},
	    {"-f", "--filter"}, {"-p", "--predict"},  {"-q", "--quiet"}};
	rs_tool_long_options(argc, argv, short_names, sizeof short_names / sizeof short_names[0]);
	/* "--bench N" (the older spelling) is --bench-samples N. */
	for (int i = 1; i + 1 < argc; ++i)
		if (!strcmp(argv[i], "--bench") && argv[i + 1][0] >= '0' && argv[i + 1][0] <= '9')
			argv[i] = "--bench-samples";
	struct rs_cli cli = {.prog = TOOL,
	                     .usage = "[options] URI  |  --bench [N]",
	                     .about = about,
	                     .options = opts,
	                     .option_count = sizeof opts / sizeof opts[0],
	                     .positional = &o->uri,
	                     .positional_max = 1,
	                     .positional_name = "URI"};
	int code;
	if (!rs_cli_parse(&cli, argc, argv, &code))
		return code ? code : -1;
	for (int i = 1; i < argc; ++i) /* --predict implies --filter, even --predict 0 */
		filter |= !strncmp(argv[i], "--predict", 9);
	o->filter = filter;
	o->quiet = quiet;
	o->reconnect = reconnect;
	o->pty = pty;
	o->bench = bench || samples != 2000;
	o->bench_samples = (int)samples;
	if (!o->uri && !o->bench)
		return rs_cli_usage_error(&cli, "no source URI");
	if (o->bench && o->uri)
		return rs_cli_usage_error(&cli, "--bench takes no source URI ('%s')", o->uri);
	/* --pty only plays the source into the pseudo-terminal: say so rather than silently
	 * ignoring a recording or filter the user asked for. */
	if (o->pty && (o->record || o->filter))
		return rs_cli_usage_error(
		    &cli, "--pty cannot be combined with --record, --filter or --predict");
	return 0;
}

static void print_stats(const struct rs_track_source *src)
{
	struct rs_track_source_stats s;
	rs_track_source_get_stats(src, &s);
	const struct rs_proto_stats *p = &s.proto;
	printf("# stats samples=%llu frames=%llu garbage_bytes=%llu crc=%llu short=%llu long=%llu "
	       "version=%llu duplicate=%llu out_of_order=%llu lost=%llu restarts=%llu "
	       "disconnects=%llu reopens=%llu\n",
	       (unsigned long long)s.samples, (unsigned long long)p->frames,
	       (unsigned long long)p->garbage_bytes, (unsigned long long)p->crc_errors,
	       (unsigned long long)p->short_frames, (unsigned long long)p->long_frames,
	       (unsigned long long)p->bad_version, (unsigned long long)p->duplicates,
	       (unsigned long long)p->out_of_order, (unsigned long long)p->lost_frames,
	       (unsigned long long)p->restarts, (unsigned long long)s.disconnects,
	       (unsigned long long)s.reopens);
	fflush(stdout);
}

/* Whether writing the output failed (a full disk, /dev/full, a closed descriptor); the
 * message is printed once. A closed pipe (EPIPE, with SIGPIPE caught) is a reader that
 * has seen enough, which ends the run cleanly instead. */
static int output_failed(int *reported)
{
	if (!ferror(stdout) || *reported)
		return *reported;
	int e = errno;
	*reported = 1;
	if (e == EPIPE) {
		stop_requested = 1;
		return 0;
	}
	fprintf(stderr, TOOL ": cannot write output: %s\n", strerror(e));
	return 1;
}

/* sim: gets the tool's layout, so the solver and the simulated markers agree. A sim that
 * is not real-time produces samples as fast as they are printed, so unbounded it would
 * fill the terminal (or a disk) within seconds: unless duration=, --count or --duration
 * bound it, it runs one pass of its script. A real-time sim runs like a device, until
 * stopped. */
static enum rs_status open_source(const struct options *o, const struct rs_pose_layout *layout,
                                  struct rs_track_source **src, struct rs_error *err)
{
	if (strncmp(o->uri, "sim:", 4) != 0)
		return rs_tracker_open(o->uri, src, err);
	static char script[512];
	struct rs_track_sim_source_desc d;
	enum rs_status st = rs_track_sim_parse_params(o->uri + 4, &d, script, sizeof script, err);
	if (st != RS_OK)
		return st;
	if (!d.realtime && d.sim.duration_s == 0 && o->count == 0 && o->duration_s == 0) {
		st = rs_sim_script_seconds(d.sim.script, &d.sim.duration_s, err);
		if (st != RS_OK)
			return st;
	}
	d.sim.layout = (const double(*)[3])layout->markers;
	return rs_track_sim_open(&d, src, err);
}

static void print_pose(const struct rs_track_source *src, const struct rs_marker_sample *s,
                       const struct rs_pose *p, const struct rs_pose_quality *q,
                       const char *solver_error)
{
	printf("%.6f seq=%u pos=[%+.5f %+.5f %+.5f] quat=[%+.5f %+.5f %+.5f %+.5f] %s "
	       "rms=%.3fmm h=%.1fmm markers=%u",
	       p->time_s, s->sequence, p->position[0], p->position[1], p->position[2],
	       p->orientation[0], p->orientation[1], p->orientation[2], p->orientation[3],
	       rs_pose_status_name(q->status), q->residual_rms_m * 1e3, q->min_height_m * 1e3,
	       q->markers_used);
#ifdef RS_HAVE_OPTICAL
	/* An optical sample's stated error (its expected error: the noise law, lens distortion
	 * included), its integrity bound (the error one undetected stray spot could cause and
	 * still pass every test, plus 5x the stated error), the poses in a row before it and,
	 * when it gave no markers, why. */
	struct rs_optical_quality oq;
	if (rs_optical_source_quality(src, &oq)) {
		printf(" stated=%.3fdeg/%.3fmm bound=%.3fdeg/%.3fmm prior=%u optical=%s",
		       oq.stated_rotation_rad * 180.0 / RS_PI, oq.stated_position_m * 1e3,
		       oq.bound_rotation_rad * 180.0 / RS_PI, oq.bound_position_m * 1e3,
		       oq.prior_frames, rs_optical_verdict_name(oq.verdict));
		/* With a layout verifier: the views it was found in where the pose puts it (0:
		 * hidden, the pose only as good as its three markers). */
		if (oq.has_verifier)
			printf(" verifier=%u", oq.verifier_views);
	}
#else
	(void)src;
#endif
	/* A pose not solved from this sample: the solver's reason, last on the line. */
	if (q->status != RS_POSE_OK && q->status != RS_POSE_RELABELED && solver_error[0])
		printf(" why=\"%s\"", solver_error);
	putchar('\n');
}

static int run(const struct options *o, const struct rs_pose_layout *layout)
{
	struct rs_error err;
	struct rs_track_source *src = NULL;
	struct rs_pose_solver *solver = NULL;
	struct rs_pose_filter *filter = NULL;
	struct rs_track_recorder *rec = NULL;
	int code = 1, started = 0, output_error = 0;
	if (open_source(o, layout, &src, &err) != RS_OK) {
		fprintf(stderr, TOOL ": cannot open '%s': %s\n", o->uri, err.message);
		return err.status == RS_ERR_PARSE || err.status == RS_ERR_INVALID ? 2 : 1;
	}
	if (o->pty) {
		code = track_serve_pty(src, o->count, o->duration_s, &stop_requested);
		rs_track_source_destroy(&src);
		return code;
	}
	struct rs_pose_solver_desc sd = {.noise_sigma_m = o->sigma_mm * 1e-3};
	if (rs_pose_solver_create(&sd, layout, &solver, &err) != RS_OK ||
	    (o->filter && rs_pose_filter_create(NULL, &filter, &err) != RS_OK) ||
	    (o->record && rs_track_recorder_create(o->record, &rec, &err) != RS_OK)) {
		fprintf(stderr, TOOL ": %s\n", err.message);
		goto out;
	}
	double start = rs_track_now_s(), next_stats = start + o->stats_every_s;
	double last_sample = start;
	double prev_q[4] = {0, 0, 0, 0}; /* zero: the first line keeps its sign */
	long long n = 0;
	/* From here on every end of the run, an error included, prints the final counters. */
	started = 1;
	for (;;) {
		if (stop_requested || (o->count && n >= o->count))
			break;
		double now = rs_track_now_s();
		if (o->duration_s > 0 && now - start >= o->duration_s)
			break;
		if (o->stats_every_s > 0 && now >= next_stats) {
			print_stats(src);
			if (output_failed(&output_error))
				goto out;
			next_stats = now + o->stats_every_s;
		}
		struct rs_marker_sample s;
		enum rs_status st = rs_track_source_read(src, &s, 100, NULL);
		if (st == RS_TIMEOUT) {
			if (rs_track_now_s() - last_sample > o->timeout_s) {
				fprintf(stderr, TOOL ": no sample for %g s from '%s'\n",
				        o->timeout_s, o->uri);
				goto out;
			}
			continue;
		}
		if (st == RS_END)
			break;
		if (st == RS_ERR_DISCONNECTED && o->reconnect) {
			fprintf(stderr, TOOL ": %s; reconnecting\n",
			        rs_track_source_last_error(src));
			enum rs_status rs;
			/* --duration still ends the run while the device stays away. */
			while (!stop_requested &&
			       !(o->duration_s > 0 && rs_track_now_s() - start >= o->duration_s) &&
			       (rs = rs_track_source_reopen(src, NULL)) != RS_OK) {
				/* Absent or busy devices come back; a source that cannot be
				 * reopened at all never will. */
				if (rs == RS_ERR_UNSUPPORTED || rs == RS_ERR_INVALID ||
				    rs == RS_ERR_PARSE || rs == RS_ERR_NO_MEMORY) {
					fprintf(stderr, TOOL ": %s\n",
					        rs_track_source_last_error(src));
					goto out;
				}
				struct timespec ts = {0, 200000000}; /* 5 tries a second */
				nanosleep(&ts, NULL);
			}
			rs_pose_filter_reset(filter);
			rs_pose_solver_reset(solver);
			last_sample = rs_track_now_s();
			continue;
		}
		if (st != RS_OK) {
			fprintf(stderr, TOOL ": %s\n", rs_track_source_last_error(src));
			goto out;
		}
		last_sample = rs_track_now_s();
		n++;
		if (rec && rs_track_recorder_write(rec, &s, &err) != RS_OK) {
			fprintf(stderr, TOOL ": %s\n", err.message);
			goto out;
		}
		struct rs_pose pose;
		struct rs_pose_quality q;
		rs_pose_solver_update(solver, &s, &pose, &q);
		if (filter && q.status != RS_POSE_NONE) {
			rs_pose_filter_update(filter, &pose, &pose, NULL);
			if (o->predict_ms > 0)
				rs_pose_filter_predict(filter, pose.time_s + o->predict_ms * 1e-3,
				                       &pose, NULL);
		}
		/* The solver hands out canonical quaternions (w >= 0), whose sign flips from
		 * line to line near 180 degrees (markers facing a camera): the printed run
		 * keeps each in the hemisphere of the line before, so it reads continuous. */
		double dot = 0;
		for (int k = 0; k < 4; ++k)
			dot += pose.orientation[k] * prev_q[k];
		for (int k = 0; k < 4 && dot < 0; ++k)
			pose.orientation[k] = -pose.orientation[k];
		memcpy(prev_q, pose.orientation, sizeof prev_q);
		if (!o->quiet)
			print_pose(src, &s, &pose, &q, rs_pose_solver_last_error(solver));
		if (output_failed(&output_error))
			goto out;
	}
	code = 0;
out:
	if (started && !output_error) {
		print_stats(src);
		if (fflush(stdout) != 0 || ferror(stdout))
			code = output_failed(&output_error) ? 1 : code;
	}
	if (rec && rs_track_recorder_destroy(&rec, &err) != RS_OK) {
		fprintf(stderr, TOOL ": %s\n", err.message);
		code = 1;
	}
	rs_pose_filter_destroy(&filter);
	rs_pose_solver_destroy(&solver);
	rs_track_source_destroy(&src);
	return code;
}

int main(int argc, char **argv)
{
	/* With descriptor 1 closed the first file the tool opens (a recording, a device)
	 * would become "stdout" and receive the pose lines. */
	if (fcntl(STDOUT_FILENO, F_GETFD) < 0) {
		fprintf(stderr, TOOL ": error: standard output is closed\n");
		return 1;
	}
	struct options o;
	int r = parse_args(argc, argv, &o);
	if (r)
		return r < 0 ? 0 : r;
	struct rs_pose_layout layout;
	struct rs_error err;
	if (o.layout) {
		if (rs_pose_layout_load(o.layout, &layout, &err) != RS_OK) {
			fprintf(stderr, TOOL ": layout %s: %s\n", o.layout, err.message);
			return 1;
		}
	} else {
		rs_pose_layout_default(&layout);
	}
	if (o.bench)
		return track_bench(o.bench_samples, &layout);
	/* Every way a run can be ended from outside finishes it cleanly (final counters, a
	 * complete --record file): a closed output pipe (SIGPIPE) or terminal (SIGHUP)
	 * included, instead of killing the tool with its recording unfinished. */
	signal(SIGINT, on_signal);
	signal(SIGTERM, on_signal);
	signal(SIGHUP, on_signal);
	signal(SIGPIPE, on_signal);
	return run(&o, &layout);
}
