package shroudedblade;

import java.io.BufferedReader;
import java.io.File;
import java.io.IOException;
import java.io.PrintWriter;
import java.nio.charset.StandardCharsets;
import java.nio.file.Files;
import java.util.ArrayList;
import java.util.LinkedHashMap;
import java.util.List;
import java.util.Locale;
import java.util.Map;

import no.ntnu.ihb.fmi4j.importer.fmi2.CoSimulationSlave;
import no.ntnu.ihb.fmi4j.importer.fmi2.Fmu;
import no.ntnu.ihb.fmi4j.modeldescription.variables.Causality;
import no.ntnu.ihb.fmi4j.modeldescription.variables.ModelVariables;
import no.ntnu.ihb.fmi4j.modeldescription.variables.TypedScalarVariable;
import no.ntnu.ihb.fmi4j.modeldescription.variables.VariableType;

/**
 * Drives an FMI 2.0 co-simulation FMU through FMI4j along an input plan and writes every output.
 *
 * <p>The plan is a CSV file written by harness/crosscheck_plan.py: a header
 * {@code time,<input>,...,<input>@<order>,...} and one row per communication point t_k. Row k
 * holds the input values set with fmi2SetReal before the step [t_k, t_{k+1}] and, in the
 * {@code name@j} columns, the j-th time derivatives set with fmi2SetRealInputDerivatives after
 * the values (the FMU resets derivatives on every fmi2SetReal). The step size passed to
 * fmi2DoStep is t_{k+1} - t_k, computed from the plan's exact times, and the communication point
 * is t_k itself: nothing is accumulated here. The last row only gives the stop time.
 *
 * <p>Output: CSV {@code time,<output>,...} with one row per communication point (row 0 after
 * initialization), values printed with Double.toString (shortest exact round trip). Prints
 * {@code wallTime=<s>} (instantiate to terminate, without JVM start-up) and the status of
 * failure on stderr; exit code 0 on success, 1 on an FMU error, 2 on bad arguments.
 */
public final class Fmi4jDriver {

    private Fmi4jDriver() {
    }

    /** One plan column: value reference and derivative order (0 = the value itself). */
    private record Column(long valueReference, int order) {
    }

    private static void usage() {
        System.err.println("usage: Fmi4jDriver --fmu FILE --plan PLAN.csv --out OUT.csv [--set name=value]...");
    }

    public static void main(String[] args) {
        String fmuPath = null;
        String planPath = null;
        String outPath = null;
        Map<String, String> settings = new LinkedHashMap<>();
        for (int i = 0; i < args.length; i++) {
            String a = args[i];
            if (i + 1 >= args.length && !a.equals("-h")) {
                usage();
                System.exit(2);
            }
            switch (a) {
                case "--fmu" -> fmuPath = args[++i];
                case "--plan" -> planPath = args[++i];
                case "--out" -> outPath = args[++i];
                case "--set" -> {
                    String kv = args[++i];
                    int eq = kv.indexOf('=');
                    if (eq <= 0) {
                        System.err.println("error: --set expects name=value, got " + kv);
                        System.exit(2);
                    }
                    settings.put(kv.substring(0, eq), kv.substring(eq + 1));
                }
                default -> {
                    usage();
                    System.exit(a.equals("-h") ? 0 : 2);
                }
            }
        }
        if (fmuPath == null || planPath == null || outPath == null) {
            usage();
            System.exit(2);
        }
        try {
            System.exit(run(new File(fmuPath), new File(planPath), new File(outPath), settings));
        } catch (IOException | IllegalArgumentException e) {
            System.err.println("error: " + e.getMessage());
            System.exit(2);
        }
    }

    private static int run(File fmuFile, File planFile, File outFile, Map<String, String> settings)
            throws IOException {
        List<String> lines = new ArrayList<>();
        try (BufferedReader r = Files.newBufferedReader(planFile.toPath(), StandardCharsets.US_ASCII)) {
            String line;
            while ((line = r.readLine()) != null) {
                if (!line.isBlank() && !line.startsWith("#")) {
                    lines.add(line);
                }
            }
        }
        if (lines.size() < 2) {
            throw new IllegalArgumentException("plan " + planFile + " needs a header and at least two rows");
        }
        String[] header = lines.get(0).split(",");
        if (!header[0].equals("time")) {
            throw new IllegalArgumentException("plan header must start with 'time'");
        }
        int nRows = lines.size() - 1;
        int nCols = header.length;
        double[][] plan = new double[nRows][nCols];
        for (int k = 0; k < nRows; k++) {
            String[] f = lines.get(k + 1).split(",");
            if (f.length != nCols) {
                throw new IllegalArgumentException("plan row " + (k + 1) + " has " + f.length + " fields, expected " + nCols);
            }
            for (int j = 0; j < nCols; j++) {
                plan[k][j] = Double.parseDouble(f[j]);
            }
        }

        long t0 = System.nanoTime();
        Fmu fmu = Fmu.from(fmuFile);
        int rc;
        try {
            CoSimulationSlave slave = fmu.asCoSimulationFmu().newInstance("blade");
            try {
                rc = simulate(slave, header, plan, settings, outFile);
            } finally {
                slave.close();
            }
        } finally {
            fmu.close();
        }
        double wall = (System.nanoTime() - t0) * 1e-9;
        System.out.println(String.format(Locale.ROOT, "wallTime=%.6f", wall));
        return rc;
    }

    private static int simulate(CoSimulationSlave slave, String[] header, double[][] plan,
                                Map<String, String> settings, File outFile) throws IOException {
        ModelVariables vars = slave.getModelVariables();

        // plan columns: "name" (value) or "name@j" (j-th derivative)
        List<Column> columns = new ArrayList<>();
        for (int j = 1; j < header.length; j++) {
            String h = header[j];
            int at = h.indexOf('@');
            String name = at < 0 ? h : h.substring(0, at);
            int order = at < 0 ? 0 : Integer.parseInt(h.substring(at + 1));
            TypedScalarVariable<?> v = vars.getByNameOrNull(name);
            if (v == null || v.getCausality() != Causality.INPUT || v.getType() != VariableType.REAL) {
                throw new IllegalArgumentException("plan column " + h + ": no Real input named " + name);
            }
            columns.add(new Column(v.getValueReference(), order));
        }

        // outputs in model-description order, Reals and Integers
        List<TypedScalarVariable<?>> outputs = new ArrayList<>();
        for (TypedScalarVariable<?> v : vars.getByCausality(Causality.OUTPUT)) {
            if (v.getType() == VariableType.REAL || v.getType() == VariableType.INTEGER) {
                outputs.add(v);
            }
        }

        int nRows = plan.length;
        double start = plan[0][0];
        double stop = plan[nRows - 1][0];
        if (!slave.setupExperiment(start, stop, 0.0)) {
            return fail("fmi2SetupExperiment", slave);
        }
        if (!slave.enterInitializationMode()) {
            return fail("fmi2EnterInitializationMode", slave);
        }
        for (Map.Entry<String, String> e : settings.entrySet()) {
            if (!applySetting(slave, vars, e.getKey(), e.getValue())) {
                return fail("setting " + e.getKey() + "=" + e.getValue(), slave);
            }
        }
        if (!setInputs(slave, columns, plan[0], false)) {
            return fail("initial inputs", slave);
        }
        if (!slave.exitInitializationMode()) {
            return fail("fmi2ExitInitializationMode", slave);
        }

        try (PrintWriter out = new PrintWriter(Files.newBufferedWriter(outFile.toPath(), StandardCharsets.US_ASCII))) {
            StringBuilder sb = new StringBuilder("time");
            for (TypedScalarVariable<?> v : outputs) {
                sb.append(',').append(v.getName());
            }
            out.println(sb);
            writeRow(out, slave, outputs, start);
            for (int k = 0; k + 1 < nRows; k++) {
                double t = plan[k][0];
                double h = plan[k + 1][0] - t;
                if (!setInputs(slave, columns, plan[k], true)) {
                    return fail("inputs at t=" + t, slave);
                }
                if (!slave.doStep(t, h)) {
                    return fail("fmi2DoStep(" + t + ", " + h + ")", slave);
                }
                writeRow(out, slave, outputs, plan[k + 1][0]);
            }
        }
        slave.terminate();
        return 0;
    }

    private static boolean applySetting(CoSimulationSlave slave, ModelVariables vars, String name, String value) {
        TypedScalarVariable<?> v = vars.getByNameOrNull(name);
        if (v == null) {
            throw new IllegalArgumentException("no variable named " + name);
        }
        long[] vr = {v.getValueReference()};
        return switch (v.getType()) {
            case REAL -> slave.writeReal(vr, new double[]{Double.parseDouble(value)}).isOK();
            case INTEGER -> slave.writeInteger(vr, new int[]{Integer.parseInt(value)}).isOK();
            case BOOLEAN -> slave.writeBoolean(vr, new boolean[]{Boolean.parseBoolean(value)}).isOK();
            default -> throw new IllegalArgumentException("unsupported type of " + name);
        };
    }

    /** fmi2SetReal of all value columns, then (inside a step) fmi2SetRealInputDerivatives. */
    private static boolean setInputs(CoSimulationSlave slave, List<Column> columns, double[] row,
                                     boolean withDerivatives) {
        List<Integer> values = new ArrayList<>();
        List<Integer> derivs = new ArrayList<>();
        for (int j = 0; j < columns.size(); j++) {
            (columns.get(j).order() == 0 ? values : derivs).add(j);
        }
        long[] vr = new long[values.size()];
        double[] val = new double[values.size()];
        for (int i = 0; i < values.size(); i++) {
            vr[i] = columns.get(values.get(i)).valueReference();
            val[i] = row[values.get(i) + 1];
        }
        if (vr.length > 0 && !slave.writeReal(vr, val).isOK()) {
            return false;
        }
        if (!withDerivatives || derivs.isEmpty()) {
            return true;
        }
        long[] dvr = new long[derivs.size()];
        int[] order = new int[derivs.size()];
        double[] dval = new double[derivs.size()];
        for (int i = 0; i < derivs.size(); i++) {
            Column c = columns.get(derivs.get(i));
            dvr[i] = c.valueReference();
            order[i] = c.order();
            dval[i] = row[derivs.get(i) + 1];
        }
        return slave.setRealInputDerivatives(dvr, order, dval).isOK();
    }

    private static void writeRow(PrintWriter out, CoSimulationSlave slave, List<TypedScalarVariable<?>> outputs,
                                 double time) {
        StringBuilder sb = new StringBuilder(Double.toString(time));
        for (TypedScalarVariable<?> v : outputs) {
            long[] vr = {v.getValueReference()};
            sb.append(',');
            if (v.getType() == VariableType.REAL) {
                double[] x = new double[1];
                slave.readReal(vr, x);
                sb.append(Double.toString(x[0]));
            } else {
                int[] x = new int[1];
                slave.readInteger(vr, x);
                sb.append(x[0]);
            }
        }
        out.println(sb);
    }

    private static int fail(String what, CoSimulationSlave slave) {
        System.err.println("error: " + what + " failed, last FMI status " + slave.getLastStatus());
        return 1;
    }
}
