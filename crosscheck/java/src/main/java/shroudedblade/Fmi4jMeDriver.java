package shroudedblade;

import java.io.File;
import java.io.IOException;
import java.io.PrintWriter;
import java.nio.charset.StandardCharsets;
import java.nio.file.Files;
import java.util.ArrayList;
import java.util.List;
import java.util.Locale;

import no.ntnu.ihb.fmi4j.FmiStatus;
import no.ntnu.ihb.fmi4j.importer.fmi2.Fmu;
import no.ntnu.ihb.fmi4j.importer.fmi2.ModelExchangeInstance;
import no.ntnu.ihb.fmi4j.modeldescription.variables.Causality;
import no.ntnu.ihb.fmi4j.modeldescription.variables.TypedScalarVariable;
import no.ntnu.ihb.fmi4j.modeldescription.variables.VariableType;

/**
 * Drives the FMI 2.0 model-exchange face of an FMU through FMI4j's ModelExchangeInstance along the
 * same input plan as Fmi4jDriver (values only: inputs held over each plan interval, as a
 * co-simulation master without input derivatives does).
 *
 * <p>FMI4j 0.38.0 imports model exchange (fmi2SetTime, fmi2SetContinuousStates, fmi2GetDerivatives,
 * fmi2GetEventIndicators, the event functions) but bundles no ODE solver, so this driver brings the
 * smallest one a user would write: classic RK4 with a fixed substep (--substep), and state events
 * located by bisection of the substep on the event indicators (to 1e-12 s), then the event iteration
 * (fmi2EnterEventMode, fmi2NewDiscreteStates until no new discrete states are needed,
 * fmi2EnterContinuousTimeMode). Output: the same CSV as Fmi4jDriver, one row per plan point.
 */
public final class Fmi4jMeDriver {

    private Fmi4jMeDriver() {
    }

    private static final double EVENT_TOLERANCE = 1e-12; // [s] width of a located event

    public static void main(String[] args) throws IOException {
        String fmuPath = null;
        String planPath = null;
        String outPath = null;
        double substep = 1e-6;
        java.util.Map<String, Double> settings = new java.util.LinkedHashMap<>(); // Real parameters, --set name=value
        for (int i = 0; i + 1 < args.length; i += 2) {
            switch (args[i]) {
                case "--fmu" -> fmuPath = args[i + 1];
                case "--plan" -> planPath = args[i + 1];
                case "--out" -> outPath = args[i + 1];
                case "--substep" -> substep = Double.parseDouble(args[i + 1]);
                case "--set" -> {
                    String kv = args[i + 1];
                    int eq = kv.indexOf('=');
                    if (eq <= 0) {
                        System.err.println("error: --set expects name=value, got " + kv);
                        System.exit(2);
                    }
                    settings.put(kv.substring(0, eq), Double.parseDouble(kv.substring(eq + 1)));
                }
                default -> {
                    System.err.println("usage: Fmi4jMeDriver --fmu FILE --plan PLAN.csv --out OUT.csv [--substep S] [--set name=value]...");
                    System.exit(2);
                }
            }
        }
        if (fmuPath == null || planPath == null || outPath == null) {
            System.err.println("usage: Fmi4jMeDriver --fmu FILE --plan PLAN.csv --out OUT.csv [--substep S]");
            System.exit(2);
        }
        List<String> lines = new ArrayList<>();
        for (String line : Files.readAllLines(new File(planPath).toPath(), StandardCharsets.US_ASCII)) {
            if (!line.isBlank() && !line.startsWith("#")) {
                lines.add(line);
            }
        }
        String[] header = lines.get(0).split(",");
        double[][] plan = new double[lines.size() - 1][];
        for (int k = 1; k < lines.size(); k++) {
            String[] f = lines.get(k).split(",");
            plan[k - 1] = new double[f.length];
            for (int j = 0; j < f.length; j++) {
                plan[k - 1][j] = Double.parseDouble(f[j]);
            }
        }
        long t0 = System.nanoTime();
        int rc;
        try (Fmu fmu = Fmu.from(new File(fmuPath))) {
            ModelExchangeInstance me = fmu.asModelExchangeFmu().newInstance("blade");
            try {
                rc = new Run(me, header, plan, substep, settings).simulate(new File(outPath));
            } finally {
                me.close();
            }
        }
        System.out.println(String.format(Locale.ROOT, "wallTime=%.6f", (System.nanoTime() - t0) * 1e-9));
        System.exit(rc);
    }

    /** One simulation: the instance, its sizes and the integrator's work arrays. */
    private static final class Run {
        final ModelExchangeInstance me;
        final String[] header;
        final double[][] plan;
        final double substep;
        final java.util.Map<String, Double> settings;
        final int nx;
        final int nz;
        final long[] inputVrs;
        final List<TypedScalarVariable<?>> outputs = new ArrayList<>();
        int events;

        Run(ModelExchangeInstance me, String[] header, double[][] plan, double substep,
            java.util.Map<String, Double> settings) {
            this.me = me;
            this.settings = settings;
            this.header = header;
            this.plan = plan;
            this.substep = substep;
            this.nx = me.getModelDescription().getNumberOfContinuousStates();
            this.nz = me.getModelDescription().getNumberOfEventIndicators();
            inputVrs = new long[header.length - 1];
            for (int j = 1; j < header.length; j++) {
                if (header[j].contains("@")) {
                    throw new IllegalArgumentException("model exchange: held inputs only (no derivative columns)");
                }
                inputVrs[j - 1] = me.getModelVariables().getByName(header[j]).getValueReference();
            }
            for (TypedScalarVariable<?> v : me.getModelVariables().getByCausality(Causality.OUTPUT)) {
                if (v.getType() == VariableType.REAL || v.getType() == VariableType.INTEGER) {
                    outputs.add(v);
                }
            }
        }

        int simulate(File outFile) throws IOException {
            double start = plan[0][0];
            double stop = plan[plan.length - 1][0];
            if (!me.setupExperiment(start, stop, 0.0) || !applySettings() || !me.enterInitializationMode()
                    || !setInputs(plan[0]) || !me.exitInitializationMode()) {
                return fail("initialization");
            }
            if (!eventIteration() || !ok(me.enterContinuousTimeMode())) {
                return fail("initial event iteration");
            }
            double[] x = new double[nx];
            me.getContinuousStates(x);
            try (PrintWriter out = new PrintWriter(Files.newBufferedWriter(outFile.toPath(), StandardCharsets.US_ASCII))) {
                StringBuilder sb = new StringBuilder("time");
                for (TypedScalarVariable<?> v : outputs) {
                    sb.append(',').append(v.getName());
                }
                out.println(sb);
                writeRow(out, start);
                for (int k = 0; k + 1 < plan.length; k++) {
                    if (!setInputs(plan[k])) {
                        return fail("inputs at t=" + plan[k][0]);
                    }
                    if (!integrate(x, plan[k][0], plan[k + 1][0])) {
                        return fail("integration in [" + plan[k][0] + ", " + plan[k + 1][0] + "]");
                    }
                    writeRow(out, plan[k + 1][0]);
                }
            }
            me.terminate();
            System.out.println("events=" + events);
            return 0;
        }

        /** RK4 substeps from t0 to t1 (the last one lands on t1); events located by bisection. */
        boolean integrate(double[] x, double t0, double t1) {
            double[] z0 = new double[nz];
            double[] z1 = new double[nz];
            if (!ok(me.getEventIndicators(z0))) {
                return false;
            }
            double t = t0;
            while (t < t1) {
                double tb = t1 - t <= substep * (1 + 1e-9) ? t1 : t + substep;
                double[] xa = x.clone();
                double[] xb = rk4(xa, t, tb - t);
                if (xb == null || !ok(me.getEventIndicators(z1))) {
                    return false;
                }
                if (!crossed(z0, z1)) {
                    System.arraycopy(xb, 0, x, 0, nx);
                    System.arraycopy(z1, 0, z0, 0, nz);
                    t = tb;
                    me.completedIntegratorStep();
                    continue;
                }
                // bisection on [t, tb] from xa: the first crossing lies in (lo, hi]
                double lo = t;
                double hi = tb;
                double[] xhi = xb;
                while (hi - lo > EVENT_TOLERANCE) {
                    double mid = 0.5 * (lo + hi);
                    double[] xm = rk4(xa, t, mid - t);
                    if (xm == null || !ok(me.getEventIndicators(z1))) {
                        return false;
                    }
                    if (crossed(z0, z1)) {
                        hi = mid;
                        xhi = xm;
                    } else {
                        lo = mid;
                    }
                }
                if (!set(hi, xhi) || !ok(me.enterEventMode()) || !eventIteration()
                        || !ok(me.enterContinuousTimeMode())) {
                    return false;
                }
                events++;
                me.getContinuousStates(x); // the event may have changed them
                if (!ok(me.getEventIndicators(z0))) {
                    return false;
                }
                t = hi; // go on from the event (a second crossing before tb is located the same way)
            }
            return set(t1, x);
        }

        /** One classic RK4 step of size h from (t, x); leaves the FMU at (t + h, result). */
        double[] rk4(double[] x, double t, double h) {
            double[] k1 = deriv(t, x);
            double[] k2 = k1 == null ? null : deriv(t + h / 2, axpy(x, h / 2, k1));
            double[] k3 = k2 == null ? null : deriv(t + h / 2, axpy(x, h / 2, k2));
            double[] k4 = k3 == null ? null : deriv(t + h, axpy(x, h, k3));
            if (k4 == null) {
                return null;
            }
            double[] r = new double[nx];
            for (int i = 0; i < nx; i++) {
                r[i] = x[i] + h / 6 * (k1[i] + 2 * k2[i] + 2 * k3[i] + k4[i]);
            }
            return set(t + h, r) ? r : null;
        }

        double[] deriv(double t, double[] x) {
            double[] dx = new double[nx];
            return set(t, x) && ok(me.getDerivatives(dx)) ? dx : null;
        }

        boolean set(double t, double[] x) {
            return ok(me.setTime(t)) && ok(me.setContinuousStates(x));
        }

        double[] axpy(double[] x, double a, double[] y) {
            double[] r = new double[nx];
            for (int i = 0; i < nx; i++) {
                r[i] = x[i] + a * y[i];
            }
            return r;
        }

        /** A sign change of any indicator (> 0 versus <= 0), as fmpy's model-exchange loop tests it. */
        boolean crossed(double[] a, double[] b) {
            for (int i = 0; i < nz; i++) {
                if ((a[i] > 0) != (b[i] > 0)) {
                    return true;
                }
            }
            return false;
        }

        boolean eventIteration() {
            for (int i = 0; i < 100; i++) {
                if (!ok(me.newDiscreteStates())) {
                    return false;
                }
                if (!me.getEventInfo$fmi_import().getNewDiscreteStatesNeeded()) {
                    return true;
                }
            }
            return false;
        }

        /** The --set values (Real parameters, e.g. Fw0 = 0 when the plan feeds aeroLoad), before initialization. */
        boolean applySettings() {
            for (java.util.Map.Entry<String, Double> e : settings.entrySet()) {
                TypedScalarVariable<?> v = me.getModelVariables().getByNameOrNull(e.getKey());
                if (v == null || v.getType() != VariableType.REAL) {
                    throw new IllegalArgumentException("--set " + e.getKey() + ": no Real variable of that name");
                }
                if (!ok(me.writeReal(new long[]{v.getValueReference()}, new double[]{e.getValue()}))) {
                    return false;
                }
            }
            return true;
        }

        boolean setInputs(double[] row) {
            double[] v = new double[inputVrs.length];
            System.arraycopy(row, 1, v, 0, v.length);
            return ok(me.writeReal(inputVrs, v));
        }

        void writeRow(PrintWriter out, double time) {
            StringBuilder sb = new StringBuilder(Double.toString(time));
            for (TypedScalarVariable<?> v : outputs) {
                long[] vr = {v.getValueReference()};
                if (v.getType() == VariableType.REAL) {
                    double[] x = new double[1];
                    me.readReal(vr, x);
                    sb.append(',').append(x[0]);
                } else {
                    int[] x = new int[1];
                    me.readInteger(vr, x);
                    sb.append(',').append(x[0]);
                }
            }
            out.println(sb);
        }

        int fail(String what) {
            System.err.println("error: " + what + " failed (last status " + me.getLastStatus() + ")");
            return 1;
        }

        static boolean ok(FmiStatus s) {
            return s == FmiStatus.OK || s == FmiStatus.Warning;
        }
    }
}
