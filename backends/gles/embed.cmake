# Embed the kernel sources into the library (nothing is read from disk at run time):
# cmake -DOUT=kernels.c -DSOURCES="a.glsl|b.glsl" -P embed.cmake writes one NUL-terminated
# char array per file, rs_gles_kernel_<name>, and a table of names and sources.
string(REPLACE "|" ";" SOURCES "${SOURCES}")
set(body "/* Generated from the backends/gles/kernels files by embed.cmake: do not edit. */\n")
string(APPEND body "#include \"kernels.h\"\n\n")
set(table "")
foreach(src IN LISTS SOURCES)
  get_filename_component(name ${src} NAME_WE)
  file(READ ${src} hex HEX)
  string(REGEX REPLACE "([0-9a-f][0-9a-f])" "0x\\1," hex "${hex}")
  string(REGEX REPLACE "(0x..,0x..,0x..,0x..,0x..,0x..,0x..,0x..,0x..,0x..,0x..,0x..,)" "\\1\n" hex "${hex}")
  string(APPEND body "static const char kernel_${name}[] = {\n${hex}0x00};\n")
  string(APPEND table "    {\"${name}.glsl\", kernel_${name}},\n")
endforeach()
string(APPEND body "\nconst struct rs_gles_kernel rs_gles_kernels[] = {\n${table}    {0, 0}};\n")
file(WRITE ${OUT}.tmp "${body}")
file(RENAME ${OUT}.tmp ${OUT})
