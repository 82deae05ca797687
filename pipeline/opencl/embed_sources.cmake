# Writes a C++ source that embeds OpenCL program files as raw string literals (run at build time with
# cmake -P; no other tool needed). Variables: ROOT (source root), FILES (paths relative to ROOT, separated
# by '|'), OUTPUT (the .cpp to write). The files are kept verbatim; kernel_sources.cpp resolves their
# #include lines at run time.
string(REPLACE "|" ";" files "${FILES}")
set(entries "")
foreach(file IN LISTS files)
  file(READ "${ROOT}/${file}" text)
  string(FIND "${text}" ")sbcl\"" clash)
  if(NOT clash EQUAL -1)
    message(FATAL_ERROR "${file} contains the raw-string delimiter )sbcl\" and cannot be embedded")
  endif()
  string(APPEND entries "      {\"${file}\", R\"sbcl(${text})sbcl\"},\n")
endforeach()
set(content "// Generated at build time by pipeline/opencl/embed_sources.cmake: do not edit.
#include \"pipeline/opencl/kernel_sources.h\"

namespace sb::opencl {

const std::vector<SourceFile>& embeddedSources() {
  static const std::vector<SourceFile> files = {
${entries}  };
  return files;
}

}  // namespace sb::opencl
")
# Rewrite only on change, so that an unchanged kernel does not recompile the embedding.
if(EXISTS "${OUTPUT}")
  file(READ "${OUTPUT}" old)
  if(old STREQUAL content)
    return()
  endif()
endif()
file(WRITE "${OUTPUT}" "${content}")
