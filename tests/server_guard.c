/* raystream-server against three misbehaviours, on loopback (issue 17, item 6):
 *   camera  a POSE with a degenerate camera (eye on its target) gets a BYE naming it;
 *   greet   64 idle connections that never say HELLO do not take the viewers' slots:
 *           4 viewers that connect after them are all WELCOMEd and get frames;
 *   stall   a viewer that stops reading for 3 s while it keeps sending poses does not
 *           then receive a backlog of old frames: prints the age of the first frames after
 *           it resumes and fails when more than one frame arrives that waited over 1 s
 *           beyond its render time (the one already on its way), for an acknowledging
 *           viewer and for a plain one with a small receive buffer (1 + the frames that
 *           buffer holds: it is the viewer's own backlog, and how many fit depends on the
 *           image, e.g. 4 of the ~1.8 kB JPEGs with all of box's lights, 3 with one).
 * usage: server_guard SERVER WORK_DIR [camera|greet|stall|stall-plain]...  (exit 0 = pass) */
#define _GNU_SOURCE
#include <arpa/inet.h>
#include <errno.h>
#include <netinet/in.h>
#include <poll.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "raystream/rs_stream.h"

static int failures;
#define CHECK(cond, ...)                                                                           \
	do {                                                                                       \
		int pass_ = (cond); /* once: a condition may read the socket */                    \
		printf("%s: ", pass_ ? "ok" : "FAIL");                                             \
		printf(__VA_ARGS__);                                                               \
		putchar('\n');                                                                     \
		failures += !pass_;                                                                \
	} while (0)

static double now_s(void)
{
	struct timespec t;
	clock_gettime(CLOCK_MONOTONIC, &t);
	return (double)t.tv_sec + (double)t.tv_nsec * 1e-9;
}

static pid_t server_pid;
static uint16_t port;

static void start_server(const char *server, const char *dir, const char *size)
{
	char port_file[512], log[512];
	snprintf(port_file, sizeof port_file, "%s/guard_port.json", dir);
	snprintf(log, sizeof log, "%s/guard_server.log", dir);
	unlink(port_file);
	server_pid = fork();
	if (server_pid == 0) {
		freopen(log, "a", stderr);
		execl(server, server, "--port", "0", "--port-file", port_file, "--size", size,
		      "--threads", "1", "--read-timeout-ms", "8000", (char *)NULL);
		_exit(127);
	}
	for (int i = 0; i < 200 && !port; ++i) {
		FILE *f = fopen(port_file, "r");
		unsigned p = 0;
		if (f && fscanf(f, " { \"port\" : %u", &p) == 1)
			port = (uint16_t)p;
		if (f)
			fclose(f);
		usleep(50000);
	}
	if (!port) {
		fprintf(stderr, "server_guard: the server did not start (see %s)\n", log);
		exit(1);
	}
}

static void stop_server(void)
{
	kill(server_pid, SIGTERM);
	waitpid(server_pid, NULL, 0);
	port = 0;
}

/* rcvbuf > 0: that receive buffer (set before connecting, so the window honours it). */
static int connect_server(int rcvbuf)
{
	struct sockaddr_in sa = {.sin_family = AF_INET, .sin_port = htons(port)};
	inet_pton(AF_INET, "127.0.0.1", &sa.sin_addr);
	int fd = socket(AF_INET, SOCK_STREAM, 0);
	if (fd >= 0 && rcvbuf > 0)
		setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &rcvbuf, sizeof rcvbuf);
	if (fd < 0 || connect(fd, (struct sockaddr *)&sa, sizeof sa) != 0) {
		perror("server_guard: connect");
		exit(1);
	}
	return fd;
}

static void send_msg(int fd, const struct rs_stream_msg *m)
{
	uint8_t b[512];
	size_t n = 0;
	if (rs_stream_encode(m, b, sizeof b, &n, NULL) != RS_OK ||
	    send(fd, b, n, MSG_NOSIGNAL) != (ssize_t)n)
		fprintf(stderr, "server_guard: send failed\n");
}

static void send_hello(int fd, uint16_t side)
{
	struct rs_stream_msg m = {.type = RS_STREAM_HELLO};
	m.u.hello.width = m.u.hello.height = side;
	send_msg(fd, &m);
}

/* A pose looking at the box scene from the front, sampled now; eye == target when bad. */
static void send_pose(int fd, uint32_t id, uint32_t flags, int bad)
{
	struct rs_stream_msg m = {.type = RS_STREAM_POSE};
	struct rs_stream_pose *p = &m.u.pose;
	*p = (struct rs_stream_pose){.pose_id = id,
	                             .flags = flags,
	                             .time_us = (uint64_t)(now_s() * 1e6),
	                             .eye = {0.5, 1.0, 4.0 + 1e-4 * id},
	                             .target = {0.5, 0.5, 0.0},
	                             .up = {0, 1, 0},
	                             .fov_y_deg = 45};
	if (bad)
		memcpy(p->target, p->eye, sizeof p->eye);
	send_msg(fd, &m);
}

struct reader {
	struct rs_stream_parser parser;
	uint8_t *buf;
};

/* The next message within timeout_s; 0 when one arrived, -1 on timeout or close. */
static int next_msg(int fd, struct reader *r, struct rs_stream_msg *m, double timeout_s)
{
	static uint8_t in[4096];
	static size_t in_len, in_off;
	static int in_fd = -1;
	if (fd != in_fd)
		in_len = in_off = 0, in_fd = fd;
	double end = now_s() + timeout_s;
	for (;;) {
		const uint8_t *d = in + in_off;
		size_t left = in_len - in_off;
		enum rs_status st = rs_stream_parser_feed(&r->parser, &d, &left, m, NULL);
		in_off = in_len - left;
		if (st == RS_OK)
			return 0;
		if (st != RS_END)
			return -1;
		double wait = end - now_s();
		struct pollfd p = {.fd = fd, .events = POLLIN};
		if (wait <= 0 || poll(&p, 1, (int)(wait * 1000) + 1) <= 0)
			return -1;
		ssize_t k = recv(fd, in, sizeof in, 0);
		if (k <= 0)
			return -1;
		in_len = (size_t)k;
		in_off = 0;
	}
}

static void reader_init(struct reader *r)
{
	size_t cap = rs_stream_parser_bound(256u * 256u * 4u);
	r->buf = malloc(cap);
	rs_stream_parser_init(&r->parser, r->buf, cap);
}

static void camera_case(void)
{
	struct reader r;
	reader_init(&r);
	int fd = connect_server(0);
	send_hello(fd, 64);
	struct rs_stream_msg m;
	int welcomed = next_msg(fd, &r, &m, 5) == 0 && m.type == RS_STREAM_WELCOME;
	CHECK(welcomed, "camera: WELCOME");
	send_pose(fd, 1, 0, 1);
	int got = -1;
	double end = now_s() + 5; /* STATS come every second: a deadline, not a message count */
	while ((got = next_msg(fd, &r, &m, end - now_s())) == 0 && m.type != RS_STREAM_BYE) {
	}
	CHECK(got == 0 && m.u.bye.reason == RS_STREAM_BYE_CAMERA &&
	          strstr(m.u.bye.text, "camera eye equals its target"),
	      "camera: a degenerate POSE gets BYE %u '%s'", got == 0 ? m.u.bye.reason : 0u,
	      got == 0 ? m.u.bye.text : "(no reply in 5 s)");
	close(fd);
	free(r.buf);
}

static void greet_case(void)
{
	int idle[64];
	for (int i = 0; i < 64; ++i)
		idle[i] = connect_server(0);
	usleep(200000);
	for (int k = 0; k < 4; ++k) {
		struct reader r;
		reader_init(&r);
		int fd = connect_server(0);
		send_hello(fd, 64);
		struct rs_stream_msg m;
		int ok = next_msg(fd, &r, &m, 5) == 0 && m.type == RS_STREAM_WELCOME;
		if (ok) {
			send_pose(fd, 1, 0, 0);
			double end = now_s() + 10;
			while ((ok = next_msg(fd, &r, &m, end - now_s()) == 0) &&
			       m.type == RS_STREAM_STATS) {
			}
			ok = ok && m.type == RS_STREAM_FRAME;
		}
		CHECK(ok,
		      "greet: viewer %d after 64 idle connections is welcomed and gets a frame%s",
		      k + 1, ok ? "" : (m.type == RS_STREAM_BYE ? ": BYE" : ""));
		if (!ok && m.type == RS_STREAM_BYE)
			printf("   (BYE %u '%s')\n", m.u.bye.reason, m.u.bye.text);
		close(fd);
		free(r.buf);
	}
	for (int i = 0; i < 64; ++i)
		close(idle[i]);
}

/* Poses every 20 ms throughout; no reading between 1 s and 4 s; then frames are read
 * (and, with acks, acknowledged) for 2 s. */
static void stall_case(int acks)
{
	const char *name = acks ? "stall (acknowledging viewer)" : "stall (plain viewer)";
	struct reader r;
	reader_init(&r);
	/* a plain viewer keeps its own receive buffer to about a frame (what is in there is its
	 * own backlog); what the server queues is what this case measures */
	int fd = connect_server(acks ? 0 : 4096);
	send_hello(fd, 128);
	struct rs_stream_msg m;
	CHECK(next_msg(fd, &r, &m, 5) == 0 && m.type == RS_STREAM_WELCOME, "%s: WELCOME", name);
	uint32_t flags = acks ? RS_STREAM_POSE_ACKS : 0, id = 0, frames = 0, old = 0;
	uint32_t smallest = UINT32_MAX; /* the smallest frame message seen, bytes */
	double t0 = now_s(), first_age = -1, last_pose = 0;
	int reading = 1, resumed = 0, n_after = 0;
	while (now_s() - t0 < 6.0) {
		double t = now_s() - t0;
		if (now_s() - last_pose >= 0.02) {
			send_pose(fd, ++id, flags, 0);
			last_pose = now_s();
		}
		reading = t < 1.0 || t >= 4.0;
		if (!reading) {
			usleep(5000);
			continue;
		}
		resumed = t >= 4.0;
		if (next_msg(fd, &r, &m, 0.01) != 0)
			continue;
		if (m.type == RS_STREAM_BYE)
			break;
		if (m.type != RS_STREAM_FRAME)
			continue;
		++frames;
		uint32_t bytes = RS_STREAM_HEADER_SIZE + RS_STREAM_FRAME_FIXED + m.u.frame.size;
		smallest = bytes < smallest ? bytes : smallest;
		if (acks) {
			struct rs_stream_msg a = {.type = RS_STREAM_STATS};
			a.u.stats.frames = frames;
			send_msg(fd, &a);
		}
		if (!resumed)
			continue;
		double age = now_s() - (double)m.u.frame.pose_time_us * 1e-6;
		if (first_age < 0)
			first_age = age;
		if (n_after < 4)
			printf("   %s: frame %d after resuming is %.0f ms old (%u bytes)\n", name,
			       n_after + 1, age * 1e3, m.u.frame.size);
		++n_after;
		/* waited in a queue: older than its own render and encode time plus 1 s (a
		 * loaded machine renders slowly; that is no backlog) */
		old += age > 1.0 + (m.u.frame.render_us + m.u.frame.encode_us) * 1e-6;
	}
	/* plain: the one on its way plus what the kernel's receive buffer (as set: Linux
	 * doubles the request) holds of the smallest frames */
	int rcv = 0;
	socklen_t len = sizeof rcv;
	getsockopt(fd, SOL_SOCKET, SO_RCVBUF, &rcv, &len);
	uint32_t allowed = acks ? 1u : 1u + (uint32_t)rcv / (smallest ? smallest : 1u);
	CHECK(n_after > 0 && old <= allowed,
	      "%s: after a 3 s stall, first frame %.0f ms old; %u of %d frames waited over 1 s "
	      "(at most %u)",
	      name, first_age * 1e3, old, n_after, allowed);
	close(fd);
	free(r.buf);
}

int main(int argc, char **argv)
{
	if (argc < 4) {
		fprintf(stderr, "usage: server_guard SERVER WORK_DIR CASE...\n");
		return 2;
	}
	signal(SIGPIPE, SIG_IGN);
	for (int i = 3; i < argc; ++i) {
		const char *c = argv[i];
		start_server(argv[1], argv[2], !strncmp(c, "stall", 5) ? "128x128" : "64x64");
		if (!strcmp(c, "camera"))
			camera_case();
		else if (!strcmp(c, "greet"))
			greet_case();
		else if (!strcmp(c, "stall"))
			stall_case(1);
		else if (!strcmp(c, "stall-plain"))
			stall_case(0);
		else
			CHECK(0, "unknown case '%s'", c);
		stop_server();
	}
	return failures ? 1 : 0;
}
