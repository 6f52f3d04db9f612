/* Test seams of the GLES renderer, private and never installed. Their code is compiled only
 * into test builds (the rs_gles_seams library, linked by test_gl_errors and test_gl_memory);
 * the shipped librs_gles.a refers to the two hooks below weakly (GCC and Clang on ELF) and,
 * where no test build defines them, the references are NULL and never called. */
#ifndef RS_GLES_SEAMS_H
#define RS_GLES_SEAMS_H

#include <stdbool.h>

#include "gl_api.h"

/* Hooks the renderer calls where they exist: rs_gl_load() hands its table to
 * rs__gl_fault_hook(); a kernel's source is rs__gles_kernel_override(name) where that
 * answers non-NULL. */
void rs__gl_fault_hook(struct rs_gl *gl) __attribute__((weak));
const char *rs__gles_kernel_override(const char *name) __attribute__((weak));
/* True: cube map captures take the readback-and-upload path, as where an RGBA16F cube face
 * is no colour attachment (the GPU path's fallback, compared against it in tests). */
bool rs__gles_capture_readback(void) __attribute__((weak));
/* True: every frame that asks for RGBA8 takes the display pass, as where the last fused
 * pass may not write it (rs_gles_step.display; compared against it in tests). */
bool rs__gles_display_unfused(void) __attribute__((weak));
/* True: a renderer created from now on finds no compute shaders in its context (as a
 * GLES 3.0 device), so RS_KERNELS_COMPUTE is refused. */
bool rs__gles_no_compute(void) __attribute__((weak));

/* gles_seams.c: compile `source` in place of kernel file `name` (NULL name: none). */
void rs__gles_override_kernel(const char *name, const char *source);

/* gles_seams.c: rs__gles_capture_readback() answers `on` from now on. */
void rs__gles_force_capture_readback(bool on);

/* gles_seams.c: rs__gles_display_unfused() answers `on` from now on. */
void rs__gles_force_display_unfused(bool on);

/* gles_seams.c: rs__gles_no_compute() answers `on` from now on. */
void rs__gles_force_no_compute(bool on);

/* gl_fault.c: out of GPU memory on demand. rs__gl_fault_wrap(true) makes every table loaded
 * from then on wrap the allocating entry points (glTexImage2D/3D, glTexStorage2D,
 * glRenderbufferStorage, glBufferData, glGenFramebuffers, glGenVertexArrays) and track live
 * texture, renderbuffer, buffer, framebuffer and vertex array names; it resets the counts.
 * rs__gl_fault_fail_at(n) restarts the allocation count: the n-th allocation from now
 * (1-based; 0: none) is not made and the next glGetError reports GL_OUT_OF_MEMORY. One
 * wrapped renderer at a time. */
void rs__gl_fault_wrap(bool on);
void rs__gl_fault_fail_at(long n);
struct rs__gl_fault_counts {
	long allocations; /* since rs__gl_fault_fail_at */
	bool fired;       /* the n-th allocation was reached and failed */
	long textures, renderbuffers, buffers, framebuffers, vertex_arrays; /* live names */
	bool overflow; /* more live names than the seam tracks: counts unreliable */
};
void rs__gl_fault_counts(struct rs__gl_fault_counts *out);

#endif
