/* html.h: text and paths written into HTML pages (report.html, a sweep's
 * index.html), so that any string, a scene path with '<' or '&' or a file
 * name with '#' say, shows as it is and links where it names. */
#ifndef WS_HTML_H
#define WS_HTML_H
#include <stdio.h>

/* Text and attribute values: the five HTML specials as entities, control
 * characters (not allowed in HTML text) as U+FFFD. NULL writes nothing. */
void ws_html_text(FILE *f, const char *s);

/* A relative path as a URL: every byte but unreserved ones and '/' is
 * percent-encoded, so that '#', '?', ':' or a space in a file name cannot
 * change what the browser loads, and nothing needs HTML escaping. NULL
 * writes nothing. */
void ws_html_url(FILE *f, const char *s);

#endif
