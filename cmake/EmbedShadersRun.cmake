# Script mode: writes OUTPUT from the shader files in INPUTS.
set(body "// Generated from shaders/ at build time; do not edit.\n#include \"gpu/shader_sources.h\"\n#include <cstring>\nnamespace yv {\nnamespace {\nstruct Entry { const char* name; const char* text; };\nconst Entry kShaders[] = {\n")
foreach(f ${INPUTS})
  get_filename_component(name ${f} NAME)
  file(READ ${f} text)
  # Raw string literal with a delimiter no shader uses.
  string(APPEND body "  {\"${name}\", R\"yvshader(${text})yvshader\"},\n")
endforeach()
string(APPEND body "};\n} // namespace\n\nconst char* shaderSource(const char* name) {\n  for (const Entry& e : kShaders)\n    if (std::strcmp(e.name, name) == 0) return e.text;\n  return nullptr;\n}\n} // namespace yv\n")
file(WRITE ${OUTPUT}.tmp "${body}")
file(RENAME ${OUTPUT}.tmp ${OUTPUT})
