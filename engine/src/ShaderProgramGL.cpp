#include <atmoglobe/engine/ShaderProgramGL.h>

#include "LoaderGL.h"

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <utility>

namespace atmoglobe::engine {

Result<std::string> loadShaderSource(std::string_view fileName) {
  if (const char* dir = std::getenv("ATMOGLOBE_SHADER_DIR"); dir && *dir) {
    const std::string path = std::string(dir) + "/" + std::string(fileName);
    std::ifstream in(path, std::ios::binary);
    if (!in) return makeError("shader " + path + ": cannot open (ATMOGLOBE_SHADER_DIR is set)");
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
  }
  auto embedded = embeddedShaderSource(fileName);
  if (!embedded) return makeError("shader " + std::string(fileName) + ": not embedded in this build");
  return std::string(*embedded);
}

namespace {
Result<GLuint> compileSource(GLenum stage, std::string_view fileName, const std::string& source,
                             const std::vector<std::string>& defines) {
  std::string text = "#version 450 core\n";
  for (const std::string& d : defines) text += "#define " + d + "\n";
  text += "#line 1\n";
  text += source;
  const GLuint shader = glCreateShader(stage);
  const char* ptr = text.c_str();
  glShaderSource(shader, 1, &ptr, nullptr);
  glCompileShader(shader);
  GLint ok = 0;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    GLint len = 0;
    glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &len);
    std::string log(static_cast<std::size_t>(len > 0 ? len : 1), '\0');
    glGetShaderInfoLog(shader, len, nullptr, log.data());
    glDeleteShader(shader);
    return makeError("shader " + std::string(fileName) + " does not compile:\n" + log);
  }
  return shader;
}
Result<GLuint> compileStage(GLenum stage, std::string_view fileName, const std::vector<std::string>& defines) {
  auto source = loadShaderSource(fileName);
  if (!source) return source.forwardError();
  return compileSource(stage, fileName, *source, defines);
}
}  // namespace

Result<ShaderProgramGL> ShaderProgramGL::create(std::string_view vertexFile, std::string_view fragmentFile,
                                                const std::vector<std::string>& defines) {
  auto fragment = loadShaderSource(fragmentFile);
  if (!fragment) return fragment.forwardError();
  return createFromSource(vertexFile, fragmentFile, *fragment, defines);
}

Result<ShaderProgramGL> ShaderProgramGL::createFromSource(std::string_view vertexFile, std::string_view fragmentName,
                                                          const std::string& fragmentSource,
                                                          const std::vector<std::string>& defines) {
  const std::string_view fragmentFile = fragmentName;
  auto vs = compileStage(GL_VERTEX_SHADER, vertexFile, defines);
  if (!vs) return vs.forwardError();
  auto fs = compileSource(GL_FRAGMENT_SHADER, fragmentFile, fragmentSource, defines);
  if (!fs) {
    glDeleteShader(*vs);
    return fs.forwardError();
  }
  ShaderProgramGL program;
  program.id_ = glCreateProgram();
  glAttachShader(program.id_, *vs);
  glAttachShader(program.id_, *fs);
  glLinkProgram(program.id_);
  glDeleteShader(*vs);
  glDeleteShader(*fs);
  GLint ok = 0;
  glGetProgramiv(program.id_, GL_LINK_STATUS, &ok);
  if (!ok) {
    GLint len = 0;
    glGetProgramiv(program.id_, GL_INFO_LOG_LENGTH, &len);
    std::string log(static_cast<std::size_t>(len > 0 ? len : 1), '\0');
    glGetProgramInfoLog(program.id_, len, nullptr, log.data());
    return makeError("program " + std::string(vertexFile) + " + " + std::string(fragmentFile) + " does not link:\n" +
                     log);
  }
  return program;
}

ShaderProgramGL::ShaderProgramGL(ShaderProgramGL&& other) noexcept : id_(std::exchange(other.id_, 0)) {}
ShaderProgramGL& ShaderProgramGL::operator=(ShaderProgramGL&& other) noexcept {
  if (this != &other) {
    if (id_) glDeleteProgram(id_);
    id_ = std::exchange(other.id_, 0);
  }
  return *this;
}
ShaderProgramGL::~ShaderProgramGL() {
  if (id_) glDeleteProgram(id_);
}

void ShaderProgramGL::use() const { glUseProgram(id_); }
GLint ShaderProgramGL::uniform(const char* name) const { return glGetUniformLocation(id_, name); }

}  // namespace atmoglobe::engine
