/* The verb dispatcher (verb.h). */
#include "popc/programs/verb.h"

#include <stdio.h>
#include <string.h>

#include "popc/util/error.h"
#include "popc/programs/usage_hint.h"

static void usage(const popc_program *p, FILE *f)
{
	fprintf(f, "usage: %s %s\n\n%s\nverbs:\n", p->name, p->synopsis, p->about);
	int width = 0;
	for (size_t i = 0; i < p->n_verbs; i++) {
		int w = (int)(strlen(p->verbs[i].name) + (p->verbs[i].args[0] ? 1 : 0) +
			      strlen(p->verbs[i].args));
		if (w > width)
			width = w;
	}
	for (size_t i = 0; i < p->n_verbs; i++) {
		const popc_verb *v = &p->verbs[i];
		int w = (int)(strlen(v->name) + (v->args[0] ? 1 : 0) + strlen(v->args));
		fprintf(f, "  %s%s%s%*s  %s\n", v->name, v->args[0] ? " " : "", v->args, width - w, "",
			v->summary);
	}
	fprintf(f, "\n%s", p->footer);
}

void popc_verb_complete(FILE *f, const popc_verb *verbs, size_t n, const char *parent)
{
	for (size_t i = 0; i < n; i++) {
		char path[128];
		snprintf(path, sizeof path, "%s%s%s", parent, parent[0] ? " " : "", verbs[i].name);
		fprintf(f, "verb\t%s\t%s\n", path, verbs[i].args);
		if (verbs[i].options)
			popc_options_complete(f, path, verbs[i].options);
		popc_verb_complete(f, verbs[i].subs, verbs[i].n_subs, path);
	}
}

int popc_verb_dispatch(const popc_program *p, int argc, char **argv)
{
	if (argc < 2) {
		usage(p, stderr);
		return POPC_EXIT_USAGE;
	}
	const char *verb = argv[1];
	if (strcmp(verb, "--help") == 0 || strcmp(verb, "-h") == 0 || strcmp(verb, "help") == 0) {
		usage(p, stdout);
		return POPC_EXIT_OK;
	}
	if (strcmp(verb, "--complete") == 0) {
		popc_verb_complete(stdout, p->verbs, p->n_verbs, "");
		return fflush(stdout) == 0 && !ferror(stdout) ? POPC_EXIT_OK : 1;
	}
	if (strcmp(verb, "--version") == 0) {
		printf("%s %s\n", p->name, p->version);
		return POPC_EXIT_OK;
	}
	for (size_t i = 0; i < p->n_verbs; i++) {
		if (strcmp(verb, p->verbs[i].name) != 0)
			continue;
		/* getopt names argv[0] in its messages: "popc run: unrecognized option" */
		static char prog[64];
		snprintf(prog, sizeof prog, "%s %s", p->name, verb);
		argv[1] = prog;
		return p->verbs[i].run(argc - 1, argv + 1);
	}
	/* the error and one hint line, not the usage: it would scroll the error away */
	fprintf(stderr, "%s: unknown verb '%s'\n", p->name, verb);
	const char *names[64];
	size_t n = 0;
	for (size_t i = 0; i < p->n_verbs && n < 64; i++)
		names[n++] = p->verbs[i].name;
	const char *near = verb[0] == '-' ? NULL : popc_nearest_name(verb, names, n);
	if (near)
		fprintf(stderr, "%s: did you mean '%s'? ('%s --help' lists the verbs)\n", p->name,
			near, p->name);
	else
		fprintf(stderr, "%s: '%s --help' lists the verbs\n", p->name, p->name);
	return POPC_EXIT_USAGE;
}
