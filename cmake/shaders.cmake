# @brief fv_add_shaders(target file...): GLSL → SPIR-V (glslangValidator), validated (spirv-val), embedded as a
# generated header <stem>_<stage>.spv.h in the build tree holding `static const uint32_t fv_spv_<stem>_<stage>[]`.
# Shaders may #include headers from their own folder and from render/include (GL_GOOGLE_include_directive).
function(fv_add_shaders target)
  set(outdir ${CMAKE_CURRENT_BINARY_DIR}/spv)
  file(MAKE_DIRECTORY ${outdir})
  set(headers)
  foreach(src ${ARGN})
    get_filename_component(abs ${src} ABSOLUTE)
    get_filename_component(name ${src} NAME)
    string(REPLACE "." "_" var ${name})
    set(spv ${outdir}/${name}.spv)
    set(hdr ${outdir}/${var}.spv.h)   # gbuffer.vert -> gbuffer_vert.spv.h, as documented above
    file(GLOB_RECURSE deps ${CMAKE_CURRENT_SOURCE_DIR}/*.h ${CMAKE_SOURCE_DIR}/render/include/*.h ${CMAKE_SOURCE_DIR}/render/include/*.glsl
         ${CMAKE_CURRENT_SOURCE_DIR}/*.glsl)
    add_custom_command(
      OUTPUT ${hdr}
      COMMAND ${GLSLANG} -V --target-env vulkan1.2 -I${CMAKE_CURRENT_SOURCE_DIR} -I${CMAKE_SOURCE_DIR}/render/include
              -o ${spv} ${abs}
      COMMAND ${SPIRV_VAL} --target-env vulkan1.2 ${spv}
      COMMAND ${GLSLANG} -V --target-env vulkan1.2 -I${CMAKE_CURRENT_SOURCE_DIR} -I${CMAKE_SOURCE_DIR}/render/include
              --vn fv_spv_${var} -o ${hdr} ${abs}
      DEPENDS ${abs} ${deps}
      COMMENT "GLSL ${name} -> SPIR-V (validated, embedded)"
      VERBATIM)
    list(APPEND headers ${hdr})
  endforeach()
  target_sources(${target} PRIVATE ${headers})
  target_include_directories(${target} PRIVATE ${outdir})
endfunction()
