#pragma once
// Private: the GL entry points the renderer uses, loaded through the active
// backend's get-proc-address (OSMesaGetProcAddress / eglGetProcAddress).
//
// Why a table and not `GL_GLEXT_PROTOTYPES` + linking libGL: libGL (glvnd)
// dispatches to the current *GLX/EGL* context, while OSMesa ships its own
// entry points; linking both makes which `glClear` runs depend on link order.
// Loading every function from the backend we created avoids that, works the
// same for both backends, and keeps GL symbols out of the rest of the program.
// Mesa returns core-profile functions from both get-proc-address calls
// (EGL_KHR_get_all_proc_addresses; OSMesa always did).

#include <GL/glcorearb.h>

#include <string>

namespace hcpf::renderer::internal {

// GL 1.1 entry points: glcorearb.h skips their typedefs when <GL/gl.h> (which
// osmesa.h includes) came first, so they are spelt out here.
using PolygonOffsetFn = void(APIENTRYP)(GLfloat factor, GLfloat units);
using GenTexturesFn = void(APIENTRYP)(GLsizei n, GLuint* textures);
using BindTextureFn = void(APIENTRYP)(GLenum target, GLuint texture);
using DeleteTexturesFn = void(APIENTRYP)(GLsizei n, const GLuint* textures);
using DrawElementsFn = void(APIENTRYP)(GLenum mode, GLsizei count, GLenum type,
                                       const void* indices);

// X(type, member, "glName")
#define HCPF_GL_FUNCTIONS(X)                                                                \
  X(PFNGLGETSTRINGPROC, GetString, "glGetString")                                           \
  X(PFNGLGETERRORPROC, GetError, "glGetError")                                              \
  X(PFNGLGETINTEGERVPROC, GetIntegerv, "glGetIntegerv")                                     \
  X(PFNGLENABLEPROC, Enable, "glEnable")                                                    \
  X(PFNGLDISABLEPROC, Disable, "glDisable")                                                 \
  X(PFNGLVIEWPORTPROC, Viewport, "glViewport")                                              \
  X(PFNGLSCISSORPROC, Scissor, "glScissor")                                                 \
  X(PFNGLCLEARPROC, Clear, "glClear")                                                       \
  X(PFNGLCLEARCOLORPROC, ClearColor, "glClearColor")                                        \
  X(PFNGLCLEARDEPTHPROC, ClearDepth, "glClearDepth")                                        \
  X(PFNGLDEPTHFUNCPROC, DepthFunc, "glDepthFunc")                                           \
  X(PFNGLDEPTHMASKPROC, DepthMask, "glDepthMask")                                           \
  X(PFNGLCOLORMASKPROC, ColorMask, "glColorMask")                                           \
  X(PFNGLCULLFACEPROC, CullFace, "glCullFace")                                              \
  X(PFNGLFRONTFACEPROC, FrontFace, "glFrontFace")                                           \
  X(PolygonOffsetFn, PolygonOffset, "glPolygonOffset")                                      \
  X(PFNGLREADPIXELSPROC, ReadPixels, "glReadPixels")                                        \
  X(PFNGLPIXELSTOREIPROC, PixelStorei, "glPixelStorei")                                     \
  X(PFNGLFINISHPROC, Finish, "glFinish")                                                    \
  X(PFNGLDRAWBUFFERPROC, DrawBuffer, "glDrawBuffer")                                        \
  X(PFNGLREADBUFFERPROC, ReadBuffer, "glReadBuffer")                                        \
  X(PFNGLGENFRAMEBUFFERSPROC, GenFramebuffers, "glGenFramebuffers")                         \
  X(PFNGLBINDFRAMEBUFFERPROC, BindFramebuffer, "glBindFramebuffer")                         \
  X(PFNGLDELETEFRAMEBUFFERSPROC, DeleteFramebuffers, "glDeleteFramebuffers")                \
  X(PFNGLFRAMEBUFFERTEXTURE2DPROC, FramebufferTexture2D, "glFramebufferTexture2D")          \
  X(PFNGLFRAMEBUFFERRENDERBUFFERPROC, FramebufferRenderbuffer, "glFramebufferRenderbuffer") \
  X(PFNGLCHECKFRAMEBUFFERSTATUSPROC, CheckFramebufferStatus, "glCheckFramebufferStatus")    \
  X(PFNGLGENRENDERBUFFERSPROC, GenRenderbuffers, "glGenRenderbuffers")                      \
  X(PFNGLBINDRENDERBUFFERPROC, BindRenderbuffer, "glBindRenderbuffer")                      \
  X(PFNGLRENDERBUFFERSTORAGEPROC, RenderbufferStorage, "glRenderbufferStorage")             \
  X(PFNGLDELETERENDERBUFFERSPROC, DeleteRenderbuffers, "glDeleteRenderbuffers")             \
  X(GenTexturesFn, GenTextures, "glGenTextures")                                            \
  X(BindTextureFn, BindTexture, "glBindTexture")                                            \
  X(PFNGLTEXIMAGE2DPROC, TexImage2D, "glTexImage2D")                                        \
  X(PFNGLGETTEXIMAGEPROC, GetTexImage, "glGetTexImage")                                     \
  X(PFNGLTEXPARAMETERIPROC, TexParameteri, "glTexParameteri")                               \
  X(PFNGLTEXPARAMETERFVPROC, TexParameterfv, "glTexParameterfv")                            \
  X(PFNGLACTIVETEXTUREPROC, ActiveTexture, "glActiveTexture")                               \
  X(DeleteTexturesFn, DeleteTextures, "glDeleteTextures")                                   \
  X(PFNGLCREATESHADERPROC, CreateShader, "glCreateShader")                                  \
  X(PFNGLSHADERSOURCEPROC, ShaderSource, "glShaderSource")                                  \
  X(PFNGLCOMPILESHADERPROC, CompileShader, "glCompileShader")                               \
  X(PFNGLGETSHADERIVPROC, GetShaderiv, "glGetShaderiv")                                     \
  X(PFNGLGETSHADERINFOLOGPROC, GetShaderInfoLog, "glGetShaderInfoLog")                      \
  X(PFNGLDELETESHADERPROC, DeleteShader, "glDeleteShader")                                  \
  X(PFNGLCREATEPROGRAMPROC, CreateProgram, "glCreateProgram")                               \
  X(PFNGLATTACHSHADERPROC, AttachShader, "glAttachShader")                                  \
  X(PFNGLLINKPROGRAMPROC, LinkProgram, "glLinkProgram")                                     \
  X(PFNGLGETPROGRAMIVPROC, GetProgramiv, "glGetProgramiv")                                  \
  X(PFNGLGETPROGRAMINFOLOGPROC, GetProgramInfoLog, "glGetProgramInfoLog")                   \
  X(PFNGLUSEPROGRAMPROC, UseProgram, "glUseProgram")                                        \
  X(PFNGLDELETEPROGRAMPROC, DeleteProgram, "glDeleteProgram")                               \
  X(PFNGLGETUNIFORMLOCATIONPROC, GetUniformLocation, "glGetUniformLocation")                \
  X(PFNGLUNIFORM1IPROC, Uniform1i, "glUniform1i")                                           \
  X(PFNGLUNIFORM1FPROC, Uniform1f, "glUniform1f")                                           \
  X(PFNGLUNIFORM2FPROC, Uniform2f, "glUniform2f")                                           \
  X(PFNGLUNIFORM3FPROC, Uniform3f, "glUniform3f")                                           \
  X(PFNGLUNIFORMMATRIX3FVPROC, UniformMatrix3fv, "glUniformMatrix3fv")                      \
  X(PFNGLUNIFORMMATRIX4FVPROC, UniformMatrix4fv, "glUniformMatrix4fv")                      \
  X(PFNGLGENVERTEXARRAYSPROC, GenVertexArrays, "glGenVertexArrays")                         \
  X(PFNGLBINDVERTEXARRAYPROC, BindVertexArray, "glBindVertexArray")                         \
  X(PFNGLDELETEVERTEXARRAYSPROC, DeleteVertexArrays, "glDeleteVertexArrays")                \
  X(PFNGLGENBUFFERSPROC, GenBuffers, "glGenBuffers")                                        \
  X(PFNGLBINDBUFFERPROC, BindBuffer, "glBindBuffer")                                        \
  X(PFNGLBUFFERDATAPROC, BufferData, "glBufferData")                                        \
  X(PFNGLDELETEBUFFERSPROC, DeleteBuffers, "glDeleteBuffers")                               \
  X(PFNGLMAPBUFFERRANGEPROC, MapBufferRange, "glMapBufferRange")                            \
  X(PFNGLUNMAPBUFFERPROC, UnmapBuffer, "glUnmapBuffer")                                     \
  X(PFNGLFENCESYNCPROC, FenceSync, "glFenceSync")                                           \
  X(PFNGLCLIENTWAITSYNCPROC, ClientWaitSync, "glClientWaitSync")                            \
  X(PFNGLDELETESYNCPROC, DeleteSync, "glDeleteSync")                                        \
  X(PFNGLFLUSHPROC, Flush, "glFlush")                                                       \
  X(PFNGLVERTEXATTRIBPOINTERPROC, VertexAttribPointer, "glVertexAttribPointer")             \
  X(PFNGLENABLEVERTEXATTRIBARRAYPROC, EnableVertexAttribArray, "glEnableVertexAttribArray") \
  X(DrawElementsFn, DrawElements, "glDrawElements")

struct GlApi {
#define HCPF_GL_MEMBER(type, member, name) type member = nullptr;
  HCPF_GL_FUNCTIONS(HCPF_GL_MEMBER)
#undef HCPF_GL_MEMBER

  using ProcLoader = void* (*)(const char* name);
  // Loads every entry point; returns the name of the first one missing, or "".
  std::string Load(ProcLoader loader);
  // Throws hcpf::RunError naming `where` and the GL error if one is pending.
  void CheckError(const char* where) const;
};

}  // namespace hcpf::renderer::internal
