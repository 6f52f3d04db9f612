# backends/gles is a one-way stack: no file calls one above it, no circle (docs/gles.md).
if(TARGET rs_gles)
  add_test(NAME gles_layers COMMAND bash ${PROJECT_SOURCE_DIR}/backends/gles/check-layers.sh)
endif()
