#pragma once
// GL shader programs built from the shader files in shaders/, which are embedded into
// the binary at build time (cmake/EmbedFiles.cmake). Setting ATMOGLOBE_SHADER_DIR makes
// them load from that directory instead (a developer override for editing shaders
// without rebuilding). GL names are plain `unsigned int` (GLuint) and uniform locations `int`
// (GLint), so that including this header needs no GL loader.
#include <atmoglobe/globe/Result.h>

#include <glm/glm.hpp>

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace atmoglobe::engine {

/// Source of an embedded shader file by name (e.g. "globe.vert"), generated at build time.
std::optional<std::string_view> embeddedShaderSource(std::string_view fileName);

/// Shader source by file name: ATMOGLOBE_SHADER_DIR override, else the embedded copy.
Result<std::string> loadShaderSource(std::string_view fileName);

class ShaderProgramGL {
 public:
  /// Compiles and links. Each stage gets "#version 450 core" and then one
  /// "#define NAME" line per entry of `defines` (variants, Magnum-style).
  static Result<ShaderProgramGL> create(std::string_view vertexFile, std::string_view fragmentFile,
                                        const std::vector<std::string>& defines = {});
  /// The same with the fragment stage's source given (assembled by the caller, e.g. the volume
  /// marcher); `fragmentName` names it in messages.
  static Result<ShaderProgramGL> createFromSource(std::string_view vertexFile, std::string_view fragmentName,
                                                  const std::string& fragmentSource,
                                                  const std::vector<std::string>& defines = {});
  ShaderProgramGL() = default;
  ShaderProgramGL(ShaderProgramGL&& other) noexcept;
  ShaderProgramGL& operator=(ShaderProgramGL&& other) noexcept;
  ~ShaderProgramGL();

  void use() const;
  unsigned int id() const { return id_; }
  int uniform(const char* name) const;

 private:
  unsigned int id_ = 0;
};

}  // namespace atmoglobe::engine
