/* paths.h: the size of every path buffer. */
#ifndef WS_PATHS_H
#define WS_PATHS_H

/* Bytes of a path buffer: Linux's PATH_MAX (4096) and room for what is
 * appended to a user's directory or file name ("/checkpoint.bin",
 * ".tmp.PID", "/rgb/test/r_12.png"). A longer path is refused or
 * truncated by snprintf, never overrun. */
#define WS_PATH_MAX 4200

#endif
