/* The kernel sources, embedded at build time (embed.cmake) from the kernels folder. */
#ifndef RS_GLES_KERNELS_H
#define RS_GLES_KERNELS_H

struct rs_gles_kernel {
	const char *name;   /* file name, "intersect.glsl" */
	const char *source; /* NUL-terminated */
};

/* Every kernel file, ended by a {NULL, NULL} entry. */
extern const struct rs_gles_kernel rs_gles_kernels[];

#endif
