/**
 * @file rs_status.h
 * Status codes, error reporting and contract checks shared by every raystream module,
 * and the two things every module, tool and app must agree on: the one monotonic clock
 * (rs_now_ms) and the one spelling of pi (RS_PI).
 *
 * One error rule for the whole library:
 * - Every fallible call returns an enum rs_status and takes an optional
 *   `struct rs_error *err` as its LAST parameter (NULL: no message wanted). Stateful
 *   objects (tracker sources, pose solver and filter) also keep their last message,
 *   retrievable with their `*_last_error()` call.
 * - Predicates return `bool` and read as questions (`rs_tracker_has_scheme()`).
 * - Bad data (a malformed file, a NaN, an index out of range, a device that misbehaves) is
 *   a status. A NULL handle or a NULL out-pointer is a programming error: it is caught by
 *   RS_ASSERT, which is always on (also with NDEBUG) and calls the handler set with
 *   rs_set_assert_handler() (default: one line on stderr, then abort()).
 * - Memory the library allocates and hands to the caller (rs_image_read_png() pixels,
 *   rs_load_view_format() text, ...) is released with rs_free().
 * The library never prints (except the default assert handler), never calls exit() and
 * never touches errno for reporting.
 */
#ifndef RS_STATUS_H
#define RS_STATUS_H

#include <stdarg.h>
#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/** Result of a fallible call: RS_OK, a negative error, or a positive non-error state. */
enum rs_status {
	RS_OK = 0,
	RS_TIMEOUT = 1,           /**< nothing arrived within the timeout (not an error) */
	RS_END = 2,               /**< end of a stream (a replay file ran out) */
	RS_ERR_INVALID = -1,      /**< a parameter or descriptor field is out of its range */
	RS_ERR_NO_MEMORY = -2,    /**< an allocation failed or a size would overflow */
	RS_ERR_IO = -3,           /**< reading or writing a file or device failed */
	RS_ERR_PARSE = -4,        /**< malformed input data */
	RS_ERR_BAD_DATA = -5,     /**< well-formed but unusable data (NaN, out-of-range index) */
	RS_ERR_UNSUPPORTED = -6,  /**< a feature, format or version this build cannot handle */
	RS_ERR_NOT_FOUND = -7,    /**< a file, device or name does not exist */
	RS_ERR_DISCONNECTED = -8, /**< a device went away; close and reopen it */
	RS_ERR_LIMIT = -9,        /**< a size exceeds what the library or driver supports */
	RS_ERR_DEVICE = -10,      /**< a device or driver call failed */
	RS_ERR_DEGENERATE = -11,  /**< geometry too degenerate for a defined answer */
};

/** Short constant name of a status ("RS_ERR_PARSE"); never NULL. */
const char *rs_status_name(enum rs_status status);

/** Capacity of an rs_error message, including the terminating NUL. */
#define RS_ERROR_MESSAGE_MAX 256

/** A caller-owned error record: the status and a one-line message naming the problem. */
struct rs_error {
	enum rs_status status;
	char message[RS_ERROR_MESSAGE_MAX];
};

/**
 * Record `status` and a printf-style message in `err` (which may be NULL) and return
 * `status`, so a failing path reads `return rs_error_set(err, RS_ERR_IO, "...", ...);`.
 * The message is truncated to fit and never contains a newline.
 */
enum rs_status rs_error_set(struct rs_error *err, enum rs_status status, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

/** Same as rs_error_set() with a va_list. */
enum rs_status rs_error_setv(struct rs_error *err, enum rs_status status, const char *fmt,
                             va_list args);

/** Reset `err` (may be NULL) to RS_OK with an empty message. */
void rs_error_clear(struct rs_error *err);

/**
 * Prepend "<printf-style context>: " to the message already in `err` (which may be NULL)
 * and return `status`, so a caller adds where a failure happened:
 * `return rs_error_prefix(err, st, "mesh %u", i);`. Truncated to fit like rs_error_set().
 */
enum rs_status rs_error_prefix(struct rs_error *err, enum rs_status status, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

/** Release memory the library allocated for the caller; NULL is allowed. */
void rs_free(void *ptr);

/**
 * Called when a contract check fails: `expr` is the failed condition as text. It must not
 * return (it may longjmp() or abort()); if it returns, the library calls abort().
 */
typedef void (*rs_assert_handler)(const char *expr, const char *file, int line, void *user);

/**
 * Install the process-wide contract-violation handler (NULL restores the default: one
 * line on stderr, then abort()). Not thread-safe: set it once, before other calls.
 */
void rs_set_assert_handler(rs_assert_handler handler, void *user);

/** Report a failed contract check to the handler; never returns. Used by RS_ASSERT. */
void rs_assert_fail(const char *expr, const char *file, int line)
#if defined(__GNUC__)
    __attribute__((noreturn))
#endif
    ;

/**
 * Milliseconds of CLOCK_MONOTONIC (an arbitrary origin; never goes back): the one clock
 * for durations and deadlines in the library, backends, tools and apps. rs_track_now_s()
 * is the same clock in seconds.
 */
double rs_now_ms(void);

/** Pi to double precision (strict C11 has no M_PI). */
#define RS_PI 3.14159265358979323846

/**
 * Contract check: always compiled in, whatever NDEBUG says (the checks are a pointer test
 * on entry to a call, not on per-ray or per-sample inner loops).
 */
#define RS_ASSERT(cond) ((cond) ? (void)0 : rs_assert_fail(#cond, __FILE__, __LINE__))

#ifdef __cplusplus
}
#endif
#endif
