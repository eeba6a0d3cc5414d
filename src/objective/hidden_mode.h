/* hidden_mode.h: which hidden-line removal the stroke images get
 * (--hidden-lines, hidden_lines.h), on its own so that the loss's options
 * (loss.h, part of the public interface) name it without the visual hull's
 * headers. */
#ifndef WS_HIDDEN_MODE_H
#define WS_HIDDEN_MODE_H

/* --hidden-lines: none (see-through, the CLIP method's sketch) or hull. */
typedef enum { WS_HIDDEN_NONE, WS_HIDDEN_HULL } ws_hidden_mode;

#endif
