/* The channel log's rows (channel_log.h). */
#include "channel_log.h"

#include "popc_config.h"

void popc_channel_log_header(FILE *f, const popc_scene *s)
{
	fprintf(f, "# popc channel log\n# format = 1\n# popc_version = %s\n# source = %s\n",
		POPC_VERSION, s->source[0] ? s->source : "(defaults)");
	popc_scene_write(s, f, "# ");
	fputs("tick,direction,seq,event,delay_ticks\n", f);
}

void popc_channel_log_event(void *user, long long k, long long seq, popc_channel_event ev,
			    long long delay_ticks)
{
	const popc_channel_log_dir *d = user;
	fprintf(d->f, "%lld,%s,%lld,%s,%lld\n", k, d->name, seq, popc_channel_event_names[ev],
		delay_ticks);
}

void popc_channel_log_in_flight(FILE *f, const char *name, long long n)
{
	fprintf(f, "# %s_in_flight = %lld\n", name, n);
}
