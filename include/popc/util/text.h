/* Small text helpers shared by the readers of scene values, log cells and
 * command-line assignments. */
#ifndef POPC_UTIL_TEXT_H
#define POPC_UTIL_TEXT_H

/* A blank, as libinih and popc's readers skip around names and values: a
 * space or a tab (a line break ends a line before anyone trims it). */
static inline int popc_is_blank(char c)
{
	return c == ' ' || c == '\t';
}

/* Narrows [*begin, *end) to the text without the blanks around it. */
static inline void popc_trim_blanks(const char **begin, const char **end)
{
	while (*begin < *end && popc_is_blank(**begin))
		(*begin)++;
	while (*end > *begin && popc_is_blank((*end)[-1]))
		(*end)--;
}

#endif
