// A one-line progress bar on stderr, redrawn in place with '\r'.
#pragma once

#include "render/renderer.h"

namespace caustic {

class ProgressBar {
public:
    /// Draws `p`; thread-safe as RenderCallbacks::onProgress requires (calls never overlap).
    void update(const RenderProgress& p);
    /// Clears the line, if anything was drawn.
    void finish();

private:
    bool drawn_ = false;
};

}  // namespace caustic
