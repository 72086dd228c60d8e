/*
 * Embedding kairos in a flight loop written in C: the driver/valve loop of examples/embed.rs
 * through the C ABI (kairos-ffi/include/kairos.h; docs/embedding.md). Load a plant model and a
 * program in one call, then each cycle hand the executive what the sensors read, by name, and
 * send what it commands, by name. The "hardware" is the driver and valve of thesis §6.1
 * (models/driver_valve.ron) simulated in a few lines: the driver relays commands once it is on,
 * the valve passes the flow when open.
 *
 * Build (tests/c_examples.rs does this and runs it):
 *   cc -I kairos-ffi/include examples/c/embed.c target/debug/libkairos_ffi.a -lpthread -ldl -lm
 *   ./a.out models/driver_valve.ron programs/valve_open.rmpl
 * Exit status: 0 when the valve opened and the executive settled, 1 otherwise.
 */
#include <stdio.h>
#include <string.h>

#include "kairos.h"

/* The device as its own firmware sees it. */
struct device {
    int driver_on;
    int valve_open;
};

/* Applies one command sent to the driver. */
static void device_command(struct device *device, const char *value) {
    if (strcmp(value, "on") == 0) {
        device->driver_on = 1;
    } else if (strcmp(value, "off") == 0) {
        device->driver_on = 0;
    } else if (strcmp(value, "open") == 0 && device->driver_on) {
        device->valve_open = 1;
    } else if (strcmp(value, "close") == 0 && device->driver_on) {
        device->valve_open = 0;
    }
}

/* Runs the loop; returns 0 when the valve opened and the executive settled. */
static int fly(KairosExecutive *executive) {
    struct device device = {0, 0};
    char believed[64] = "";
    for (int cycle = 0; cycle < 50; cycle++) {
        double now = cycle * 0.1;
        /* What the flow sensors read. */
        KairosObservation observed[2] = {
            {"valve.flow_in", KAIROS_VALUE_SYMBOL, "nominal", 0.0},
            {"valve.flow_out", KAIROS_VALUE_SYMBOL, device.valve_open ? "nominal" : "zero", 0.0},
        };
        KairosStep *step = NULL;
        KairosStatus status = kairos_step(executive, now, observed, 2, &step);
        if (status != KAIROS_STATUS_OK) {
            fprintf(stderr, "step failed (%d): %s\n", (int)status, kairos_executive_last_error(executive));
            return 1;
        }
        KairosStepSummary summary = kairos_step_summary(step);
        /* The valve's most likely mode (component 1 of the model), when it changes. */
        KairosNamedValue valve = kairos_step_mode(step, 1);
        if (valve.value != NULL && strcmp(valve.value, believed) != 0) {
            printf("%5.1f s  believed %s = %s (the most likely state: p %.2f)\n", now, valve.variable,
                   valve.value, kairos_step_estimate_probability(step, 0));
            snprintf(believed, sizeof believed, "%s", valve.value);
        }
        /* Events worded as the mission log words them, with the plant's and program's names. */
        for (size_t i = 0; i < summary.event_count; i++) {
            printf("%5.1f s  event %s\n", now, kairos_step_event(step, i).line);
        }
        for (size_t i = 0; i < summary.command_count; i++) {
            KairosNamedValue command = kairos_step_command(step, i);
            printf("%5.1f s  send %s = %s\n", now, command.variable, command.value);
            device_command(&device, command.value);
        }
        int settled = (summary.flags & KAIROS_STEP_SETTLED) != 0;
        kairos_step_free(step);
        if (settled) {
            printf("%5.1f s  settled\n", now);
            return device.valve_open ? 0 : 1;
        }
    }
    fprintf(stderr, "the valve did not open in 5 s\n");
    return 1;
}

int main(int argc, char **argv) {
    if (argc != 3) {
        fprintf(stderr, "usage: %s PLANT PROGRAM\n", argv[0]);
        return 2;
    }
    KairosOptions options = kairos_options_default();
    options.kappa = 10;
    options.estimates = 1;
    KairosExecutive *executive = NULL;
    char *error = NULL;
    KairosStatus status = kairos_executive_load(argv[1], argv[2], &options, &executive, &error);
    if (status != KAIROS_STATUS_OK) {
        fprintf(stderr, "%s\n", error);
        kairos_string_free(error);
        return 2;
    }
    int outcome = fly(executive);
    kairos_executive_free(executive);
    return outcome;
}
