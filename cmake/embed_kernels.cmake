# Embeds OpenCL kernel files into a generated C++ source, so the program runs
# from any folder. The generated file defines pfill::embedded_kernel_source()
# (declared in include/pfill/embedded_kernels.hpp); it is rebuilt whenever a
# .cl file changes.
set(PFILL_EMBED_SCRIPT ${CMAKE_CURRENT_LIST_DIR}/embed_kernels_run.cmake)

function(pfill_embed_kernels OUTPUT)
  set(files ${ARGN})
  add_custom_command(
    OUTPUT ${OUTPUT}
    COMMAND ${CMAKE_COMMAND} -DOUTPUT=${OUTPUT} "-DFILES=${files}" -P ${PFILL_EMBED_SCRIPT}
    DEPENDS ${files} ${PFILL_EMBED_SCRIPT}
    COMMENT "Embedding OpenCL kernels"
    VERBATIM)
endfunction()
