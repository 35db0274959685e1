#include "gl_texture.h"

namespace hcpf::renderer::internal {

GLuint UploadTexture(const GlApi& gl, const Texture8& t, bool repeat) {
  GLuint tex = 0;
  gl.GenTextures(1, &tex);
  gl.BindTexture(GL_TEXTURE_2D, tex);
  gl.PixelStorei(GL_UNPACK_ALIGNMENT, 1);
  const GLenum format = t.channels == 3 ? GL_RGB : GL_RED;
  const GLint internal_format = t.channels == 3 ? GL_RGB8 : GL_R8;
  gl.TexImage2D(GL_TEXTURE_2D, 0, internal_format, t.size, t.size, 0, format, GL_UNSIGNED_BYTE,
                t.texels.data());
  int levels = 1;
  if (repeat) {
    Texture8 level = t;
    while (level.size > 1) {
      level = HalveTexture(level);
      gl.TexImage2D(GL_TEXTURE_2D, levels++, internal_format, level.size, level.size, 0, format,
                    GL_UNSIGNED_BYTE, level.texels.data());
    }
  }
  gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_BASE_LEVEL, 0);
  gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, levels - 1);
  gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER,
                   repeat ? GL_LINEAR_MIPMAP_NEAREST : GL_LINEAR);
  gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  const GLint wrap = repeat ? GL_REPEAT : GL_CLAMP_TO_EDGE;
  gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, wrap);
  gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, wrap);
  return tex;
}

}  // namespace hcpf::renderer::internal
