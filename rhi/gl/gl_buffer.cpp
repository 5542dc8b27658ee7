// GL backend: buffers. One immutable-storage buffer object per rhi buffer; usage flags need no
// GL counterpart (any buffer object can be bound anywhere).
#include <cstring>

#include "rhi/gl/gl_device.h"

namespace parity::rhi::gl {

BufferHandle GlDevice::createBuffer(const BufferDesc& desc) {
  auto buffer = std::make_unique<GlBuffer>();
  buffer->desc = desc;
  buffer->desc.initialData = nullptr;  // not owned past this call
  gl.CreateBuffers(1, &buffer->name);
  // rhi buffers start zeroed; GL leaves storage without data undefined.
  std::vector<uint8_t> zeros;
  const void* data = desc.initialData;
  if (!data) {
    zeros.assign(desc.size, 0);
    data = zeros.data();
  }
  gl.NamedBufferStorage(buffer->name, static_cast<GLsizeiptr>(desc.size), data, GL_DYNAMIC_STORAGE_BIT);
  label(GL_BUFFER, buffer->name, desc.label);
  return buffers_.add(std::move(buffer));
}

void GlDevice::destroy(BufferHandle h) {
  std::optional<std::unique_ptr<GlBuffer>> buffer = buffers_.remove(h);
  if (!buffer) return;
  for (const GlTexelView& v : (*buffer)->texelViews) gl.DeleteTextures(1, &v.name);
  gl.DeleteBuffers(1, &(*buffer)->name);
  for (VertexBufferBinding& vb : vertexBuffers_)
    if (vb.buffer == h) vb = {};
  if (indexBuffer_ == h) indexBuffer_ = {};
}

GLuint GlDevice::texelView(GlBuffer& buffer, Format format, size_t offset, size_t size) {
  for (const GlTexelView& v : buffer.texelViews)
    if (v.format == format && v.offset == offset && v.size == size) return v.name;
  GlTexelView v{format, offset, size, 0};
  gl.CreateTextures(GL_TEXTURE_BUFFER, 1, &v.name);
  gl.TextureBufferRange(v.name, glFormat(format).internalFormat, buffer.name, static_cast<GLintptr>(offset),
                        static_cast<GLsizeiptr>(size));
  buffer.texelViews.push_back(v);
  return v.name;
}

const BufferDesc* GlDevice::describe(BufferHandle h) const {
  const std::unique_ptr<GlBuffer>* buffer = buffers_.get(h);
  return buffer ? &(*buffer)->desc : nullptr;
}

void GlDevice::writeBuffer(BufferHandle h, size_t offset, const void* data, size_t size) {
  std::unique_ptr<GlBuffer>* buffer = buffers_.get(h);
  if (!buffer || size == 0) return;
  // GL orders this after every draw and dispatch already issued that reads the buffer.
  gl.NamedBufferSubData((*buffer)->name, static_cast<GLintptr>(offset), static_cast<GLsizeiptr>(size), data);
}

std::vector<uint8_t> GlDevice::readBuffer(BufferHandle h, size_t offset, size_t size) {
  std::unique_ptr<GlBuffer>* buffer = buffers_.get(h);
  if (!buffer) return {};
  std::vector<uint8_t> out(size);
  if (size == 0) return out;
  // Waits for all earlier commands writing the buffer (shader writes are made visible by the
  // barrier after every dispatch and pass).
  gl.GetNamedBufferSubData((*buffer)->name, static_cast<GLintptr>(offset), static_cast<GLsizeiptr>(size),
                           out.data());
  return out;
}

void GlDevice::copyBuffer(BufferHandle src, size_t srcOffset, BufferHandle dst, size_t dstOffset, size_t size) {
  std::unique_ptr<GlBuffer>* s = buffers_.get(src);
  std::unique_ptr<GlBuffer>* d = buffers_.get(dst);
  if (!s || !d || size == 0) return;
  gl.CopyNamedBufferSubData((*s)->name, (*d)->name, static_cast<GLintptr>(srcOffset),
                            static_cast<GLintptr>(dstOffset), static_cast<GLsizeiptr>(size));
}

}  // namespace parity::rhi::gl
